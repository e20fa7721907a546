#pragma once
// The station's empty scene as files (interfaces.md §2): background_frontal.png
// and background_lateral.png, 8-bit grey or colour (colour is read as its
// luma), each the frames' width × height. `spinewatch background` writes
// them, `record` copies them into recordings, `replay` and the daemon load
// them (docs/tuning.md, "Background").
#include <array>
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include "spinewatch/frames/frame.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

inline constexpr std::array<std::string_view, 2> kBackgroundFiles = {"background_frontal.png", "background_lateral.png"};

struct GreyImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // packed rows
  LumaView view() const { return {pixels.data(), width, height, width, 1}; }
};

struct BackgroundImages {
  GreyImage frontal, lateral;
};

// Both files exist in `dir` (one without the other is an error when loading).
bool has_background_images(const std::filesystem::path& dir);
// Errors name the file and the problem (unreadable, not an image, sizes
// that differ from each other or from `expected_width` × `expected_height`
// when given).
Result<BackgroundImages> load_background_images(const std::filesystem::path& frontal,
                                                const std::filesystem::path& lateral, int expected_width = 0,
                                                int expected_height = 0);
Result<BackgroundImages> load_background_images(const std::filesystem::path& dir, int expected_width = 0,
                                                int expected_height = 0);
// Writes both PNGs into `dir` (created when missing).
Status write_background_images(const std::filesystem::path& dir, const BackgroundImages& images);

}  // namespace spinewatch
