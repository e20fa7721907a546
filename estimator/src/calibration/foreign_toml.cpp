// caliscope's camera_array.toml and anipose's calibration.toml
// (foreign_calibration.hpp has what each field means).
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <toml++/toml.h>

#include "calibration/foreign_readers.hpp"

namespace spinewatch::foreign_detail {
namespace {

// Where a field is, for messages: "FILE:LINE: cameras.0.matrix".
struct Place {
  const std::string& file;
  std::string table;
  std::string at(const toml::node& node, std::string_view key) const {
    return fmt::format("{}:{}: {}.{}", file, node.source().begin.line, table, key);
  }
};

Result<std::vector<double>> numbers(const toml::array& array, const std::string& where) {
  std::vector<double> out;
  for (const toml::node& n : array) {
    if (!n.is_number()) return Error{fmt::format("{}: expected numbers", where)};
    out.push_back(*n.value<double>());
  }
  return out;
}

Result<std::vector<double>> number_list(const toml::table& t, std::string_view key, const Place& place) {
  const toml::node* n = t.get(key);
  if (!n) return Error{fmt::format("{}: missing", place.at(t, key))};
  const toml::array* a = n->as_array();
  if (!a) return Error{fmt::format("{}: expected an array of numbers", place.at(*n, key))};
  return numbers(*a, place.at(*n, key));
}

// A 3×3 matrix as three rows of three numbers.
Result<Eigen::Matrix3d> matrix3(const toml::table& t, std::string_view key, const Place& place) {
  const toml::node* n = t.get(key);
  if (!n) return Error{fmt::format("{}: missing", place.at(t, key))};
  const toml::array* rows = n->as_array();
  const std::string where = place.at(*n, key);
  if (!rows || rows->size() != 3) return Error{fmt::format("{}: expected 3 rows of 3 numbers", where)};
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    const toml::array* row = (*rows)[static_cast<std::size_t>(r)].as_array();
    if (!row || row->size() != 3) return Error{fmt::format("{}: row {}: expected 3 numbers", where, r + 1)};
    auto v = numbers(*row, where);
    if (!v) return v.error();
    for (int c = 0; c < 3; ++c) m(r, c) = (*v)[static_cast<std::size_t>(c)];
  }
  return m;
}

// Rotation as a 3×3 matrix (caliscope) or a Rodrigues vector (anipose).
Result<Eigen::Matrix3d> rotation(const toml::table& t, const Place& place) {
  const toml::node* n = t.get("rotation");
  const toml::array* a = n ? n->as_array() : nullptr;
  if (a && a->size() == 3 && (*a)[0].is_number()) {
    auto v = numbers(*a, place.at(*n, "rotation"));
    if (!v) return v.error();
    const Eigen::Vector3d r((*v)[0], (*v)[1], (*v)[2]);
    const double angle = r.norm();
    if (angle < 1e-15) return Eigen::Matrix3d::Identity().eval();
    return Eigen::AngleAxisd(angle, r / angle).toRotationMatrix();
  }
  return matrix3(t, "rotation", place);
}

Status read_intrinsics(const toml::table& t, const Place& place, CameraModel& model) {
  auto size = number_list(t, "size", place);
  if (!size) return size.error();
  if (size->size() != 2 || !((*size)[0] >= 1 && (*size)[1] >= 1 && (*size)[0] <= 65536 && (*size)[1] <= 65536))
    return Error{fmt::format("{}: expected [width, height] in pixels", place.at(*t.get("size"), "size"))};
  model.image_width = static_cast<int>((*size)[0]);
  model.image_height = static_cast<int>((*size)[1]);
  auto K = matrix3(t, "matrix", place);
  if (!K) return K.error();
  model.camera_matrix = *K;
  auto d = number_list(t, "distortions", place);
  if (!d) return d.error();
  // A flattened 1×N from some writers is the same list.
  if (std::find(kDistortionLengths.begin(), kDistortionLengths.end(), static_cast<int>(d->size())) ==
      kDistortionLengths.end())
    return Error{fmt::format("{}: {} coefficients; OpenCV's model has 4, 5, 8, 12 or 14",
                             place.at(*t.get("distortions"), "distortions"), d->size())};
  std::copy(d->begin(), d->end(), model.dist_coeffs.begin());
  return Ok{};
}

// Rotation and translation, both or neither (then has_extrinsics = false).
Status read_extrinsics(const toml::table& t, const Place& place, double to_mm, NamedCamera& cam) {
  const bool has_r = t.contains("rotation"), has_t = t.contains("translation");
  if (!has_r && !has_t) {
    cam.has_extrinsics = false;
    return Ok{};
  }
  if (has_r != has_t)
    return Error{fmt::format("{}: rotation and translation come together", place.at(t, has_r ? "translation" : "rotation"))};
  auto R = rotation(t, place);
  if (!R) return R.error();
  auto tr = number_list(t, "translation", place);
  if (!tr) return tr.error();
  if (tr->size() != 3)
    return Error{fmt::format("{}: expected 3 numbers", place.at(*t.get("translation"), "translation"))};
  cam.model.R = *R;
  cam.model.t = Eigen::Vector3d((*tr)[0], (*tr)[1], (*tr)[2]) * to_mm;
  return Ok{};
}

template <class T>
T value_or(const toml::table& t, std::string_view key, T fallback) {
  const toml::node* n = t.get(key);
  if (!n) return fallback;
  return n->value<T>().value_or(fallback);
}

Result<NamedCamera> read_camera(const toml::table& t, const Place& place, double to_mm) {
  NamedCamera cam;
  if (auto s = read_intrinsics(t, place, cam.model); !s) return s.error();
  if (auto s = read_extrinsics(t, place, to_mm, cam); !s) return s.error();
  cam.rms_px = value_or(t, "error", -1.0);
  cam.ignored = value_or(t, "ignore", false);
  cam.rotation_count = static_cast<int>(value_or<std::int64_t>(t, "rotation_count", 0));
  if (auto s = check_camera(cam.model, fmt::format("{}:{}: {}", place.file, t.source().begin.line, place.table)); !s)
    return s.error();
  return cam;
}

// caliscope: [cameras.N], translation in metres.
Result<CameraArray> read_caliscope(const toml::table& cameras, const std::string& file) {
  CameraArray array;
  array.format = "caliscope";
  array.source = file;
  for (const auto& [key, node] : cameras) {
    const toml::table* t = node.as_table();
    if (!t) continue;
    Place place{file, fmt::format("cameras.{}", key.str())};
    auto cam = read_camera(*t, place, 1000.0);
    if (!cam) return cam.error();
    cam->id = std::string(key.str());
    cam->name = "cam_" + cam->id;
    array.cameras.push_back(std::move(*cam));
  }
  if (array.cameras.empty()) return Error{fmt::format("{}: [cameras] holds no camera tables", file)};
  array.notes.push_back("caliscope camera_array.toml: translation in metres, converted to millimetres");
  return array;
}

double largest_baseline(const std::vector<NamedCamera>& cameras) {
  double largest = 0;
  for (std::size_t i = 0; i < cameras.size(); ++i)
    for (std::size_t j = i + 1; j < cameras.size(); ++j)
      largest = std::max(largest,
                         (cameras[i].model.centre_in_world() - cameras[j].model.centre_in_world()).norm());
  return largest;
}

// anipose / aniposelib (and caliscope's older per-camera [cam_N] tables,
// which carry `port`): every top-level table with a `matrix`.
Result<CameraArray> read_anipose(const toml::table& root, const std::string& file) {
  CameraArray array;
  array.format = "anipose";
  array.source = file;
  bool metres_declared = false;
  for (const auto& [key, node] : root) {
    const toml::table* t = node.as_table();
    if (!t || !t->contains("matrix")) continue;
    Place place{file, std::string(key.str())};
    if (t->contains("port")) metres_declared = true;  // caliscope's older layout
    auto cam = read_camera(*t, place, 1.0);
    if (!cam) return cam.error();
    cam->id = std::string(key.str());
    cam->name = value_or<std::string>(*t, "name", cam->id);
    array.cameras.push_back(std::move(*cam));
  }
  if (array.cameras.empty()) return Error{fmt::format("{}: no camera tables (with a matrix)", file)};
  // Units are the calibration board's. A room's cameras stand metres
  // apart: within 20 units of each other they are metres, not millimetres.
  const double baseline = largest_baseline(array.cameras);
  if (metres_declared || (array.cameras.size() >= 2 && baseline > 0 && baseline < 20)) {
    for (NamedCamera& cam : array.cameras) cam.model.t *= 1000.0;
    array.notes.push_back(fmt::format("{}: translation taken as metres (cameras at most {:.3g} units apart), "
                                      "converted to millimetres",
                                      file, baseline));
  } else {
    array.notes.push_back(fmt::format("{}: translation taken as millimetres (cameras up to {:.0f} units apart)",
                                      file, baseline));
  }
  if (metres_declared) array.format = "caliscope";
  return array;
}

}  // namespace

Result<CameraArray> read_toml_array(const std::string& text, const std::string& file) {
  toml::table root;
  try {
    root = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    return Error{fmt::format("{}:{}: {}", file, e.source().begin.line, e.description())};
  }
  if (const toml::table* cameras = root["cameras"].as_table()) return read_caliscope(*cameras, file);
  return read_anipose(root, file);
}

}  // namespace spinewatch::foreign_detail
