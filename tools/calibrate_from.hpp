#pragma once
// spinewatch calibrate --from FILE: another tool's calibration (caliscope,
// anipose, OpenCV YAML/JSON; docs/import.md) written as the station's
// calibration.yaml, two cameras in the station's world frame. Kept apart
// from cmd_calibrate.cpp, which calibrates from board views.
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "command.hpp"

namespace spinewatch::cli {

struct CalibrateFromOptions {
  std::vector<std::string> from;  // FILE, or FORMAT FILE ("caliscope camera_array.toml")
  std::string cameras, up;
  double camera_height_mm = 1100;
};

// Adds --from, and --cameras, --up, --camera-height where `cmd` has none
// of that name yet: call it after the command's own options.
std::shared_ptr<CalibrateFromOptions> add_calibrate_from_options(CLI::App* cmd);

// When --from was given: converts it to `out` (or fails) and returns true;
// otherwise does nothing and returns false.
bool run_calibrate_from(const CalibrateFromOptions& options, const std::string& out, ExitCode& exit_code);

}  // namespace spinewatch::cli
