#include "calibrate_from.hpp"

#include <array>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "spinewatch/import/station_rig.hpp"

namespace spinewatch::cli {

std::shared_ptr<CalibrateFromOptions> add_calibrate_from_options(CLI::App* cmd) {
  auto o = std::make_shared<CalibrateFromOptions>();
  cmd->add_option("--from", o->from,
                  "[FORMAT] FILE: convert another tool's calibration (caliscope camera_array.toml, anipose "
                  "calibration.toml, OpenCV YAML/JSON) instead of calibrating from views")
      ->expected(1, 2);
  // Added last, so an option of the same name that the board calibration
  // already has is left to it.
  if (!cmd->get_option_no_throw("--cameras"))
    cmd->add_option("--cameras", o->cameras, "--from: F,L, the two cameras of a multi-camera file by id or name");
  if (!cmd->get_option_no_throw("--up"))
    cmd->add_option("--up", o->up, "--from: X,Y,Z, the up direction in the file's frame (default: estimated)");
  if (!cmd->get_option_no_throw("--camera-height"))
    cmd->add_option("--camera-height", o->camera_height_mm, "--from: the cameras' mean height above the floor, mm")
        ->check(CLI::Range(0.0, 10000.0))
        ->capture_default_str();
  return o;
}

bool run_calibrate_from(const CalibrateFromOptions& o, const std::string& out, ExitCode& exit_code) {
  if (o.from.empty()) return false;
  import::RigChoice choice;
  choice.calibration = o.from.back();
  choice.up = o.up;
  choice.camera_height_mm = o.camera_height_mm;
  if (!o.cameras.empty()) {
    const std::size_t comma = o.cameras.find(',');
    if (comma == std::string::npos || comma == 0 || comma + 1 == o.cameras.size()) {
      exit_code.fail(Error{fmt::format("calibrate: --cameras \"{}\": expected FRONTAL,LATERAL", o.cameras)}, 2);
      return true;
    }
    choice.frontal = o.cameras.substr(0, comma);
    choice.lateral = o.cameras.substr(comma + 1);
  }
  auto station = import::station_rig_from(choice);
  if (!station) {
    exit_code.fail(station.error());
    return true;
  }
  if (o.from.size() == 2) {
    const std::string& said = o.from.front();
    const bool matches = said == station->format || (said == "opencv" && station->format.rfind("opencv", 0) == 0);
    if (!matches) {
      exit_code.fail(Error{fmt::format("calibrate --from {} {}: the file is {}, not {}", said, o.from.back(),
                                       station->format, said)});
      return true;
    }
  }
  for (const std::string& line : station->report) spdlog::info("{}", line);
  if (auto s = save_calibration(out, station->rig); !s) {
    exit_code.fail(s.error());
    return true;
  }
  const std::array<const CameraModel*, 2> cams = {&station->rig.frontal, &station->rig.lateral};
  for (int v = 0; v < 2; ++v)
    fmt::print("{}: camera {}, {}x{}, fx {:.1f} fy {:.1f} cx {:.1f} cy {:.1f}\n", v == 0 ? "frontal" : "lateral",
               station->ids[v], cams[v]->image_width, cams[v]->image_height, cams[v]->camera_matrix(0, 0),
               cams[v]->camera_matrix(1, 1), cams[v]->camera_matrix(0, 2), cams[v]->camera_matrix(1, 2));
  fmt::print("wrote {}\ncheck it with:  spinewatch check --calibration {}\n", out, out);
  return true;
}

}  // namespace spinewatch::cli
