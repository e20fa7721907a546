#pragma once
// The station's empty scene as files (docs/interfaces.md §2): background_frontal.png
// and background_lateral.png, 8-bit grey or colour, each the frames' width
// × height. Colour is read into YUYV (luma and chroma, for the silhouette's
// colour test) and written from it, through OpenCV's full-range BT.601
// YCrCb: a grey reader sees the same luma, and a round trip keeps Y, U and
// V within a level. `spinewatch background` writes
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

// One camera's empty scene: grey (step 1) or YUYV (step 2), packed rows.
struct SceneImage {
  int width = 0, height = 0;
  int step = 1;
  std::vector<std::uint8_t> pixels;
  LumaView view() const { return {pixels.data(), width, height, static_cast<std::ptrdiff_t>(width) * step, step}; }
  bool colour() const { return step == 2; }
};

struct BackgroundImages {
  SceneImage frontal, lateral;
};

// Both files exist in `dir` (one without the other is an error when loading).
bool has_background_images(const std::filesystem::path& dir);
// Errors name the file and the problem (unreadable, not a PNG, not 8-bit,
// sizes that differ from each other or from `expected_width` ×
// `expected_height` when given, or beyond 4096 a side). The size is taken
// from the PNG's header before anything is decoded.
Result<BackgroundImages> load_background_images(const std::filesystem::path& frontal,
                                                const std::filesystem::path& lateral, int expected_width = 0,
                                                int expected_height = 0);
Result<BackgroundImages> load_background_images(const std::filesystem::path& dir, int expected_width = 0,
                                                int expected_height = 0);
// Writes both PNGs into `dir` (created when missing).
Status write_background_images(const std::filesystem::path& dir, const BackgroundImages& images);

}  // namespace spinewatch
