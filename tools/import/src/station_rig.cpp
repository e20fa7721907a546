#include "spinewatch/import/station_rig.hpp"

#include <fmt/format.h>

#include "spinewatch/estimator/calibration/foreign_calibration.hpp"
#include "spinewatch/import/world_frame.hpp"

namespace spinewatch::import {

Result<StationRig> station_rig_from(const RigChoice& choice) {
  auto array = load_camera_array(choice.calibration);
  if (!array) return array.error();
  StationRig out;
  out.format = array->format;
  out.report = array->notes;
  out.ids[0] = choice.frontal;
  out.ids[1] = choice.lateral;
  auto file_rig = select_pair(*array, choice.frontal, choice.lateral);
  if (!file_rig) return file_rig.error();
  const bool defaulted = choice.frontal.empty();
  if (defaulted) {
    // select_pair took the first two usable cameras; name them.
    int k = 0;
    for (const NamedCamera& cam : array->cameras)
      if (k < 2 && !cam.ignored && cam.has_extrinsics) out.ids[k++] = cam.id;
  }
  out.report.push_back(fmt::format("{} ({}): frontal camera {}, lateral camera {}{}", choice.calibration.string(),
                                   array->format, out.ids[0], out.ids[1],
                                   defaulted ? " (the first two; --cameras F,L to choose)" : ""));
  Eigen::Vector3d up;
  if (!choice.up.empty()) {
    auto given = parse_up(choice.up);
    if (!given) return given.error();
    up = *given;
    out.report.push_back(fmt::format("world frame: up ({:.3f}, {:.3f}, {:.3f}) in the calibration's frame (--up)",
                                     up.x(), up.y(), up.z()));
  } else {
    std::vector<std::string> lines;
    auto estimated = estimate_up(*array, lines);
    if (!estimated) return estimated.error();
    up = *estimated;
    for (const std::string& line : lines) out.report.push_back("world frame: " + line);
  }
  auto frame = choose_world_frame(*file_rig, up, choice.camera_height_mm);
  if (!frame) return frame.error();
  for (const std::string& line : frame->report) out.report.push_back("world frame: " + line);
  out.rig = CameraRig{frame->to_station(file_rig->frontal), frame->to_station(file_rig->lateral)};
  out.frame = std::move(*frame);
  return out;
}

}  // namespace spinewatch::import
