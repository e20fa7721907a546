// The station's calibration written as OpenCV FileStorage JSON: the nodes
// frontal and lateral, each with camera_matrix, dist_coeffs, R, t as
// {"type_id": "opencv-matrix", "rows", "cols", "dt", "data"}. Read with
// nlohmann::json rather than cv::FileStorage, whose JSON reader the
// station does not trust with arbitrary input (storage_precheck.cpp).
#include <algorithm>
#include <initializer_list>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "calibration/foreign_readers.hpp"

namespace spinewatch::foreign_detail {
namespace {

using nlohmann::json;

const json* find_any(const json& node, std::initializer_list<const char*> keys) {
  for (const char* key : keys)
    if (auto it = node.find(key); it != node.end()) return &*it;
  return nullptr;
}

// An opencv-matrix (or a plain array of numbers) as its numbers and shape.
Result<std::vector<double>> matrix_data(const json* node, const std::string& where, int& rows, int& cols) {
  if (!node) return Error{fmt::format("{}: missing", where)};
  const json* data = node;
  rows = cols = 0;
  if (node->is_object()) {
    data = find_any(*node, {"data"});
    const json* r = find_any(*node, {"rows"});
    const json* c = find_any(*node, {"cols"});
    if (!data || !r || !c || !r->is_number_integer() || !c->is_number_integer())
      return Error{fmt::format("{}: expected an opencv-matrix with rows, cols and data", where)};
    rows = r->get<int>();
    cols = c->get<int>();
  }
  if (!data->is_array()) return Error{fmt::format("{}: expected an array of numbers", where)};
  std::vector<double> out;
  for (const json& v : *data) {
    if (!v.is_number()) return Error{fmt::format("{}: expected numbers", where)};
    out.push_back(v.get<double>());
  }
  if (rows == 0) {
    rows = static_cast<int>(out.size());
    cols = 1;
  }
  if (static_cast<long>(rows) * cols != static_cast<long>(out.size()))
    return Error{fmt::format("{}: {}×{} but {} numbers", where, rows, cols, out.size())};
  return out;
}

Result<Eigen::Matrix3d> matrix3(const json& cam, std::initializer_list<const char*> keys, const std::string& where) {
  int rows = 0, cols = 0;
  auto v = matrix_data(find_any(cam, keys), where, rows, cols);
  if (!v) return v.error();
  if (v->size() != 9) return Error{fmt::format("{}: expected 3×3, got {} numbers", where, v->size())};
  Eigen::Matrix3d m;
  for (int k = 0; k < 9; ++k) m(k / 3, k % 3) = (*v)[static_cast<std::size_t>(k)];
  return m;
}

Result<NamedCamera> read_camera(const json& root, const std::string& file, const char* id) {
  const std::string where = fmt::format("{}: {}", file, id);
  auto it = root.find(id);
  if (it == root.end() || !it->is_object()) return Error{fmt::format("{}: missing", where)};
  const json& cam = *it;
  NamedCamera out;
  out.id = out.name = id;
  auto K = matrix3(cam, {"camera_matrix", "Camera_Matrix", "cameraMatrix"}, where + ".camera_matrix");
  if (!K) return K.error();
  out.model.camera_matrix = *K;
  int rows = 0, cols = 0;
  auto d = matrix_data(find_any(cam, {"dist_coeffs", "distortion_coefficients", "Distortion_Coefficients"}),
                       where + ".dist_coeffs", rows, cols);
  if (!d) return d.error();
  if (std::find(kDistortionLengths.begin(), kDistortionLengths.end(), static_cast<int>(d->size())) ==
      kDistortionLengths.end())
    return Error{fmt::format("{}.dist_coeffs: {} coefficients; OpenCV's model has 4, 5, 8, 12 or 14", where, d->size())};
  std::copy(d->begin(), d->end(), out.model.dist_coeffs.begin());
  auto R = matrix3(cam, {"R"}, where + ".R");
  if (!R) return R.error();
  out.model.R = *R;
  auto t = matrix_data(find_any(cam, {"t"}), where + ".t", rows, cols);
  if (!t) return t.error();
  if (t->size() != 3) return Error{fmt::format("{}.t: expected 3 numbers", where)};
  out.model.t = Eigen::Vector3d((*t)[0], (*t)[1], (*t)[2]);
  const json* w = find_any(cam, {"image_width"});
  const json* h = find_any(cam, {"image_height"});
  if (w && h && w->is_number_integer() && h->is_number_integer()) {
    out.model.image_width = w->get<int>();
    out.model.image_height = h->get<int>();
  }
  if (auto s = check_camera(out.model, where); !s) return s.error();
  return out;
}

}  // namespace

Result<CameraArray> read_opencv_json(const std::string& text, const std::string& file) {
  const json root = json::parse(text, nullptr, false);
  if (root.is_discarded() || !root.is_object())
    return Error{fmt::format("{}: not a JSON object (OpenCV FileStorage JSON with frontal and lateral)", file)};
  CameraArray array;
  array.format = "opencv-json";
  array.source = file;
  for (const char* id : {"frontal", "lateral"}) {
    auto cam = read_camera(root, file, id);
    if (!cam) return cam.error();
    array.cameras.push_back(std::move(*cam));
  }
  return array;
}

}  // namespace spinewatch::foreign_detail
