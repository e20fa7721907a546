#pragma once
// What OpenCV 4.6's FileStorage reader cannot be trusted with, refused
// before it sees a file (calibration_io.cpp reads through it after this).
#include <cstdint>
#include <string>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// Which FileStorage formats a reader takes: calibration.yaml is YAML
// (docs/interfaces.md §2); one camera's intrinsics from OpenCV's samples may be
// XML too (the calibration tutorial writes out_camera_data.xml).
enum class StorageFormats : std::uint8_t { YamlOnly, YamlOrXml };

// Ok when `text` (the contents of `file`) is a file OpenCV may read:
// YAML in the line forms OpenCV's own writer produces, or (where allowed)
// XML after a whole declaration. Otherwise one message naming the file and,
// for YAML, the line.
Status check_before_opencv(const std::string& text, const std::string& file, StorageFormats formats);

}  // namespace spinewatch
