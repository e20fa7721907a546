#include "spinewatch/estimator/calibration/foreign_calibration.hpp"

#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "calibration/foreign_readers.hpp"
#include "spinewatch/frames/text_file.hpp"

namespace spinewatch {
namespace foreign_detail {

Status check_camera(const CameraModel& model, const std::string& where) {
  const Eigen::Matrix3d& K = model.camera_matrix;
  if (!K.allFinite() || !model.R.allFinite() || !model.t.allFinite())
    return Error{fmt::format("{}: a value that is not a finite number", where)};
  if (!(K(0, 0) > 0 && K(1, 1) > 0))
    return Error{fmt::format("{}: matrix: focal lengths fx = {}, fy = {} must be positive", where, K(0, 0), K(1, 1))};
  const double orthonormality = (model.R * model.R.transpose() - Eigen::Matrix3d::Identity()).norm();
  if (orthonormality > 1e-3 || model.R.determinant() < 0)
    return Error{fmt::format("{}: rotation: not a rotation matrix (|R·Rᵀ − I| = {:.3g}, det = {:.3g})", where,
                             orthonormality, model.R.determinant())};
  for (double d : model.dist_coeffs)
    if (!std::isfinite(d)) return Error{fmt::format("{}: distortions: a value that is not a finite number", where)};
  return Ok{};
}

}  // namespace foreign_detail

namespace {

Result<CameraArray> read_station_yaml(const std::filesystem::path& path) {
  auto rig = load_calibration(path);
  if (!rig) return rig.error();
  CameraArray array;
  array.format = "opencv-yaml";
  array.source = path.string();
  for (const auto& [id, model] : {std::pair{"frontal", &rig->frontal}, std::pair{"lateral", &rig->lateral}}) {
    NamedCamera cam;
    cam.id = cam.name = id;
    cam.model = *model;
    array.cameras.push_back(std::move(cam));
  }
  return array;
}

bool usable(const NamedCamera& cam) { return !cam.ignored && cam.has_extrinsics; }

}  // namespace

Result<CameraArray> load_camera_array(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) return Error{fmt::format("{}: no such file", file)};
  auto text = read_text_file(path);
  if (!text) return text.error();
  const std::size_t first = text->find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return Error{fmt::format("{}: empty file", file)};
  if ((*text)[first] == '{') return foreign_detail::read_opencv_json(*text, file);
  if (text->compare(first, 5, "%YAML") == 0) return read_station_yaml(path);
  auto toml = foreign_detail::read_toml_array(*text, file);
  if (toml) return toml;
  // Not TOML of a known kind: the station's YAML, whose errors say more
  // about a YAML file; a file that is neither gets both messages.
  auto yaml = read_station_yaml(path);
  if (yaml) return yaml;
  return Error{fmt::format("{} (read as TOML: {}; as OpenCV YAML: {}). Accepted: caliscope camera_array.toml, "
                           "anipose calibration.toml, OpenCV YAML/JSON with frontal and lateral (docs/import.md)",
                           file, toml.error().message, yaml.error().message)};
}

std::string list_cameras(const CameraArray& array) {
  std::string out;
  for (const NamedCamera& cam : array.cameras) {
    if (!out.empty()) out += ", ";
    out += cam.id == cam.name ? cam.id : fmt::format("{} ({})", cam.id, cam.name);
    if (cam.ignored) out += " [ignored]";
    else if (!cam.has_extrinsics) out += " [no extrinsics]";
  }
  return out;
}

Result<const NamedCamera*> find_camera(const CameraArray& array, std::string_view id_or_name) {
  for (const NamedCamera& cam : array.cameras)
    if (cam.id == id_or_name) return &cam;
  for (const NamedCamera& cam : array.cameras)
    if (cam.name == id_or_name) return &cam;
  return Error{fmt::format("{}: no camera \"{}\" in this {} file; its cameras are {} (give them by id or name, "
                           "e.g. --cameras {},{})",
                           array.source, id_or_name, array.format, list_cameras(array),
                           array.cameras.empty() ? "A" : array.cameras[0].id,
                           array.cameras.size() < 2 ? "B" : array.cameras[1].id)};
}

Result<CameraRig> select_pair(const CameraArray& array, std::string_view frontal, std::string_view lateral) {
  std::string wanted[2] = {std::string(frontal), std::string(lateral)};
  if (wanted[0].empty() && wanted[1].empty()) {
    std::vector<const NamedCamera*> candidates;
    for (const NamedCamera& cam : array.cameras)
      if (usable(cam)) candidates.push_back(&cam);
    if (candidates.size() < 2)
      return Error{fmt::format("{}: fewer than two usable cameras (with extrinsics, not ignored): {}", array.source,
                               list_cameras(array))};
    wanted[0] = candidates[0]->id;
    wanted[1] = candidates[1]->id;
  } else if (wanted[0].empty() || wanted[1].empty()) {
    return Error{fmt::format("{}: name both cameras (frontal and lateral); the file holds {}", array.source,
                             list_cameras(array))};
  }
  const NamedCamera* chosen[2] = {nullptr, nullptr};
  for (int k = 0; k < 2; ++k) {
    auto cam = find_camera(array, wanted[k]);
    if (!cam) return cam.error();
    if ((*cam)->ignored)
      return Error{fmt::format("{}: camera {} is marked ignore = true (left out of the calibration); choose another "
                               "of {}",
                               array.source, wanted[k], list_cameras(array))};
    if (!(*cam)->has_extrinsics)
      return Error{fmt::format("{}: camera {} has intrinsics only (no rotation/translation): calibrate the array's "
                               "extrinsics first, or choose another of {}",
                               array.source, wanted[k], list_cameras(array))};
    chosen[k] = *cam;
  }
  if (chosen[0] == chosen[1])
    return Error{fmt::format("{}: the frontal and the lateral camera are the same camera ({}); choose two of {}",
                             array.source, chosen[0]->id, list_cameras(array))};
  return CameraRig{chosen[0]->model, chosen[1]->model};
}

}  // namespace spinewatch
