#pragma once
// Saves what a camera saw as a PNG, for looking at phantom frames.
#include <filesystem>

#include "spinewatch/frames/frame.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::test {

Status save_luma_png(const LumaView& luma, const std::filesystem::path& path);

}  // namespace spinewatch::test
