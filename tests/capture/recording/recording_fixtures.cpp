#include "recording_fixtures.hpp"

#include <fstream>
#include <random>

#include "test_support.hpp"

namespace spinewatch::test {

std::vector<std::uint8_t> pattern_bytes(std::size_t size, std::uint32_t seed) {
  std::mt19937 rng(seed * 2654435761u + 17);
  std::vector<std::uint8_t> bytes(size);
  for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
  return bytes;
}

Frame pattern_frame(const FrameFormat& format, FrameInfo info, std::uint32_t seed) {
  return Frame::owning(format, info, pattern_bytes(format.frame_bytes(), seed));
}

void append_raw(const std::filesystem::path& raw, const FrameFormat& format, std::size_t count,
                std::uint32_t first_seed, std::size_t extra_bytes) {
  std::ofstream out(raw, std::ios::binary | std::ios::app);
  for (std::size_t i = 0; i < count; ++i) {
    const auto bytes = pattern_bytes(format.frame_bytes(), first_seed + static_cast<std::uint32_t>(i));
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
  const auto tail = pattern_bytes(extra_bytes, 999);
  out.write(reinterpret_cast<const char*>(tail.data()), static_cast<std::streamsize>(tail.size()));
}

void write_raw_recording(const std::filesystem::path& dir, const FrameFormat& format, std::size_t frames,
                         const std::string& json) {
  std::filesystem::create_directories(dir);
  for (const char* name : {"frontal.raw", "lateral.raw"}) std::filesystem::remove(dir / name);
  append_raw(dir / "frontal.raw", format, frames, 0);
  append_raw(dir / "lateral.raw", format, frames, 1000);
  write_file(dir / "recording.json", json);
}

std::vector<std::uint8_t> to_vector(std::span<const std::uint8_t> bytes) { return {bytes.begin(), bytes.end()}; }

}  // namespace spinewatch::test
