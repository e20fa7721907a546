#pragma once
// Builders for recording directories in tests: frames with distinct,
// reproducible bytes, and raw files written the way v4l2-ctl writes them.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "spinewatch/capture/recording.hpp"

namespace spinewatch::test {

// Pseudo-random bytes determined by (seed, size): two frames with different
// seeds differ, and a test can rebuild the expected content.
std::vector<std::uint8_t> pattern_bytes(std::size_t size, std::uint32_t seed);

Frame pattern_frame(const FrameFormat& format, FrameInfo info, std::uint32_t seed);

// Appends `count` whole frames (seeds first_seed, first_seed+1, …) plus
// `extra_bytes` to a raw file, with plain file writes like v4l2-ctl.
void append_raw(const std::filesystem::path& raw, const FrameFormat& format, std::size_t count,
                std::uint32_t first_seed, std::size_t extra_bytes = 0);

// A directory with (fresh) frontal.raw and lateral.raw of `frames` frames each and
// the given recording.json text.
void write_raw_recording(const std::filesystem::path& dir, const FrameFormat& format, std::size_t frames,
                         const std::string& json);

std::vector<std::uint8_t> to_vector(std::span<const std::uint8_t> bytes);

}  // namespace spinewatch::test
