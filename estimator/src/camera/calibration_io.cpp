// calibration.yaml through cv::FileStorage, so that files written by
// OpenCV tools (and by us) read back exactly. Besides the project's own
// keys (docs/interfaces.md §2) a camera node may use the keys of OpenCV's
// calibration samples and tools; each quantity has one accepted set of
// spellings and a node that gives two of them is an error, not a guess.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

#include "spinewatch/frames/printable.hpp"
#include "spinewatch/frames/text_file.hpp"

#include <opencv2/core.hpp>
#include <Eigen/Dense>
#include <opencv2/core/eigen.hpp>

#include "camera/storage_precheck.hpp"
#include "spinewatch/estimator/camera_model.hpp"

namespace spinewatch {
namespace {

constexpr std::array<const char*, 3> kCameraMatrixKeys = {"camera_matrix", "Camera_Matrix", "cameraMatrix"};
constexpr std::array<const char*, 3> kDistortionKeys = {"dist_coeffs", "distortion_coefficients",
                                                        "Distortion_Coefficients"};
constexpr std::array<const char*, 2> kWidthKeys = {"image_width", "image_Width"};
constexpr std::array<const char*, 2> kHeightKeys = {"image_height", "image_Height"};

// The key of `keys` present in `node`: nothing when none is, an error when
// more than one is (which would the user mean?).
template <std::size_t N>
Result<std::optional<std::string>> find_key(const cv::FileNode& node, const std::string& where,
                                            const std::array<const char*, N>& keys) {
  std::optional<std::string> found;
  for (const char* key : keys) {
    if (node[key].empty()) continue;
    if (found) return Error{fmt::format("{}{}: also given as {}; keep one", where, *found, key)};
    found = key;
  }
  return found;
}

// OpenCV sizes a matrix from its header before it reads the data, so a
// corrupt header ("cols: 2147483647") would have it allocate gigabytes:
// the header is checked first. No matrix here has more than 9 elements.
Status check_matrix_header(const cv::FileNode& node, const std::string& where, const char* key) {
  constexpr int kMaxSide = 16;
  const auto small = [](const cv::FileNode& n) { return n.isInt() && int(n) >= 1 && int(n) <= kMaxSide; };
  const auto bad = [&] {
    return Error{fmt::format("{}{}: not a matrix (rows and cols must be integers 1..{})", where, key, kMaxSide)};
  };
  if (!node.isMap()) return Error{fmt::format("{}{}: not a matrix", where, key)};
  if (const cv::FileNode sizes = node["sizes"]; !sizes.empty()) {  // opencv-nd-matrix
    if (!sizes.isSeq() || sizes.size() < 1 || sizes.size() > 2) return bad();
    for (const cv::FileNode& side : sizes)
      if (!small(side)) return bad();
    return Ok{};
  }
  if (!small(node["rows"]) || !small(node["cols"])) return bad();
  return Ok{};
}

Result<cv::Mat> read_any_matrix(const cv::FileNode& camera, const std::string& where, const std::string& key) {
  if (auto header = check_matrix_header(camera[key], where, key.c_str()); !header) return header.error();
  cv::Mat m;
  try {
    camera[key] >> m;
  } catch (const std::exception&) {  // cv::Exception, or a standard one from OpenCV's reader
    return Error{fmt::format("{}{}: not a matrix", where, key)};
  }
  if (m.empty()) return Error{fmt::format("{}{}: not a matrix", where, key)};
  if (m.channels() != 1) return Error{fmt::format("{}{}: {} channels, expected 1", where, key, m.channels())};
  m.convertTo(m, CV_64F);
  for (int i = 0; i < m.rows * m.cols; ++i)
    if (!std::isfinite(m.at<double>(i)))
      return Error{fmt::format("{}{}: element {} is not finite", where, key, i)};
  return m;
}

Result<cv::Mat> read_matrix(const cv::FileNode& camera, const std::string& where, const std::string& key, int rows,
                            int cols) {
  if (camera[key].empty()) return Error{fmt::format("{}{}: missing", where, key)};
  auto m = read_any_matrix(camera, where, key);
  if (!m) return m;
  if (m->rows * m->cols == rows * cols && (m->rows == 1 || m->cols == 1) && (rows == 1 || cols == 1))
    *m = m->reshape(1, rows);
  if (m->rows != rows || m->cols != cols)
    return Error{fmt::format("{}{}: expected {}x{}, got {}x{}", where, key, rows, cols, m->rows, m->cols)};
  return m;
}

// Keys that mean another lens model than OpenCV's pinhole one: refused by
// name rather than read as if they were pinhole coefficients.
Status refuse_other_models(const cv::FileNode& node, const std::string& where) {
  if (const cv::FileNode model = node["distortion_model"]; !model.empty()) {
    const std::string name = model.isString() ? model.string() : std::string("?");
    if (name != "plumb_bob" && name != "rational_polynomial")
      return Error{fmt::format("{}distortion_model: '{}' cannot be mapped onto OpenCV's pinhole model (plumb_bob, "
                               "rational_polynomial); calibrate the camera with `spinewatch calibrate` instead",
                               where, name)};
  }
  if (!node["xi"].empty())
    return Error{fmt::format("{}xi: an omnidirectional (cv::omnidir) calibration cannot be mapped onto OpenCV's "
                             "pinhole model; calibrate the camera with `spinewatch calibrate` instead",
                             where)};
  return Ok{};
}

// camera_matrix, the distortion and the image size of one camera (the
// intrinsics), from `node` under any of the accepted spellings.
Result<CameraModel> read_intrinsics(const cv::FileNode& node, const std::string& where) {
  if (auto s = refuse_other_models(node, where); !s) return s.error();
  auto k_key = find_key(node, where, kCameraMatrixKeys);
  if (!k_key) return k_key.error();
  auto K = read_matrix(node, where, k_key->value_or("camera_matrix"), 3, 3);
  if (!K) return K.error();

  auto d_key = find_key(node, where, kDistortionKeys);
  if (!d_key) return d_key.error();
  const std::string dist_key = d_key->value_or("dist_coeffs");
  if (!*d_key) return Error{fmt::format("{}{}: missing", where, dist_key)};
  auto dist = read_any_matrix(node, where, dist_key);
  if (!dist) return dist.error();
  const int n = dist->rows * dist->cols;
  if (dist->rows != 1 && dist->cols != 1)
    return Error{fmt::format("{}{}: expected a row or column of coefficients, got {}x{}", where, dist_key,
                             dist->rows, dist->cols)};
  if (std::find(kDistortionLengths.begin(), kDistortionLengths.end(), n) == kDistortionLengths.end())
    return Error{fmt::format("{}{}: {} coefficients; OpenCV's models have 4, 5, 8, 12 or 14 (k1 k2 p1 p2 [k3 [k4 k5 "
                             "k6 [s1 s2 s3 s4 [τx τy]]]])",
                             where, dist_key, n)};

  CameraModel cam;
  cv::cv2eigen(*K, cam.camera_matrix);
  for (int i = 0; i < n; ++i) cam.dist_coeffs[static_cast<std::size_t>(i)] = dist->at<double>(i);
  if (cam.camera_matrix(0, 0) <= 0 || cam.camera_matrix(1, 1) <= 0)
    return Error{fmt::format("{}{}: focal lengths must be positive", where, k_key->value_or("camera_matrix"))};

  auto w_key = find_key(node, where, kWidthKeys);
  if (!w_key) return w_key.error();
  auto h_key = find_key(node, where, kHeightKeys);
  if (!h_key) return h_key.error();
  if (w_key->has_value() != h_key->has_value())
    return Error{fmt::format("{}{}: given without {}", where, w_key->value_or(h_key->value_or("")),
                             w_key->has_value() ? "image_height" : "image_width")};
  if (*w_key) {
    for (const std::string& key : {**w_key, **h_key})
      if (!node[key].isInt() || static_cast<int>(node[key]) <= 0)
        return Error{fmt::format("{}{}: expected a positive whole number of pixels", where, key)};
    cam.image_width = static_cast<int>(node[**w_key]);
    cam.image_height = static_cast<int>(node[**h_key]);
  }
  return cam;
}

Result<CameraModel> read_camera(const cv::FileStorage& fs, const std::string& file, const char* name) {
  const cv::FileNode node = fs[name];
  // Keys are named "file: camera.key".
  const std::string where = fmt::format("{}: {}.", file, name);
  if (node.empty() || !node.isMap()) {
    // One camera's intrinsics at the top level (OpenCV's calibration
    // samples write that): it says nothing about where either camera is.
    if (auto key = find_key(fs.root(), file + ": ", kCameraMatrixKeys); key && *key)
      return Error{fmt::format("{}: one camera's intrinsics ({} at the top level), not a station's calibration: the "
                               "`frontal` and `lateral` nodes are missing. Give it to `spinewatch calibrate "
                               "--frontal-intrinsics` or `--lateral-intrinsics`, which adds where the cameras stand "
                               "(docs/calibration.md)",
                               file, **key)};
    return Error{fmt::format("{}: {}: missing camera node", file, name)};
  }
  auto cam = read_intrinsics(node, where);
  if (!cam) return cam;
  auto R = read_matrix(node, where, "R", 3, 3);
  if (!R) return R.error();
  auto t = read_matrix(node, where, "t", 3, 1);
  if (!t) return t.error();
  cv::cv2eigen(*R, cam->R);
  cv::cv2eigen(*t, cam->t);
  const double orthonormality = (cam->R * cam->R.transpose() - Eigen::Matrix3d::Identity()).norm();
  if (orthonormality > 1e-3 || cam->R.determinant() < 0)
    return Error{fmt::format("{}R: not a rotation matrix (|R·Rᵀ − I| = {:.3g}, det = {:.3g})", where,
                             orthonormality, cam->R.determinant())};
  return cam;
}

// Opens `path` for reading after check_before_opencv (storage_precheck.hpp). Every use of the
// FileStorage must stay inside read_guarded's try: OpenCV's reader throws
// cv::Exception from places a caller would not expect (indexing a root
// that is not a map) and lets standard exceptions through
// (std::length_error) — both found by the calibration_yaml fuzzer
// (tests/fuzz), both ended the program before.
template <typename T, typename Read>
Result<T> read_guarded(const std::filesystem::path& path, StorageFormats formats, const char* expected, Read&& read) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) return Error{fmt::format("{}: no such file", file)};
  auto text = read_text_file(path);
  if (!text) return text.error();
  if (auto checked = check_before_opencv(*text, file, formats); !checked) return checked.error();
  try {
    cv::FileStorage fs;
    if (!fs.open(file, cv::FileStorage::READ)) return Error{fmt::format("{}: cannot be read", file)};
    if (!fs.root().isMap()) return Error{fmt::format("{}: expected a map with {}", file, expected)};
    return read(fs, file);
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{}: not an OpenCV FileStorage file ({})", file, printable(e.err))};
  } catch (const std::exception& e) {
    return Error{fmt::format("{}: not an OpenCV FileStorage file ({})", file, printable(e.what()))};
  }
}

}  // namespace

Result<CameraRig> load_calibration(const std::filesystem::path& path) {
  return read_guarded<CameraRig>(path, StorageFormats::YamlOnly, "the nodes frontal and lateral",
                                 [](cv::FileStorage& fs, const std::string& file) -> Result<CameraRig> {
    auto frontal = read_camera(fs, file, "frontal");
    if (!frontal) return frontal.error();
    auto lateral = read_camera(fs, file, "lateral");
    if (!lateral) return lateral.error();
    return CameraRig{*frontal, *lateral};
  });
}

Result<CameraModel> load_intrinsics(const std::filesystem::path& path) {
  return read_guarded<CameraModel>(path, StorageFormats::YamlOrXml, "camera_matrix and distortion_coefficients",
                                   [](cv::FileStorage& fs, const std::string& file) -> Result<CameraModel> {
    const cv::FileNode root = fs.root();
    auto key = find_key(root, file + ": ", kCameraMatrixKeys);
    if (!key) return key.error();
    if (!*key) {
      if (!fs["frontal"].empty() || !fs["lateral"].empty())
        return Error{fmt::format("{}: a station's calibration (frontal, lateral), not one camera's intrinsics; "
                                 "use it as calibration.yaml",
                                 file)};
      return Error{fmt::format("{}: camera_matrix: missing (nor Camera_Matrix, cameraMatrix)", file)};
    }
    return read_intrinsics(root, file + ": ");
  });
}

Status save_intrinsics(const std::filesystem::path& path, const CameraModel& camera) {
  try {
    cv::FileStorage fs(path.string(), cv::FileStorage::WRITE);
    if (!fs.isOpened()) return Error{fmt::format("{}: cannot be written", path.string())};
    cv::Mat K;
    cv::eigen2cv(camera.camera_matrix, K);
    const cv::Mat dist(camera.distortion(), true);
    fs << "camera_matrix" << K << "distortion_coefficients" << dist.reshape(1, 1);
    if (camera.image_width > 0) fs << "image_width" << camera.image_width << "image_height" << camera.image_height;
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{}: {}", path.string(), e.err)};
  }
  return Ok{};
}

Status check_image_size(const CameraRig& rig, int width, int height) {
  for (const auto& [name, cam] : {std::pair{"frontal", &rig.frontal}, std::pair{"lateral", &rig.lateral}}) {
    if (cam->image_width == 0) continue;
    if (cam->image_width != width || cam->image_height != height)
      return Error{fmt::format("{}: calibrated at {}x{} (image_width, image_height) but the stream is {}x{}: a "
                               "calibration holds only at the resolution it was made at; calibrate again at {}x{} "
                               "(docs/calibration.md)",
                               name, cam->image_width, cam->image_height, width, height, width, height)};
  }
  return Ok{};
}

Status save_calibration(const std::filesystem::path& path, const CameraRig& rig) {
  try {
    cv::FileStorage fs(path.string(), cv::FileStorage::WRITE);
    if (!fs.isOpened()) return Error{fmt::format("{}: cannot be written", path.string())};
    auto write_camera = [&fs](const char* name, const CameraModel& cam) {
      cv::Mat K, R, t;
      cv::eigen2cv(cam.camera_matrix, K);
      cv::eigen2cv(cam.R, R);
      cv::eigen2cv(cam.t, t);
      const cv::Mat dist(cam.distortion(), true);
      fs << name << "{" << "camera_matrix" << K << "dist_coeffs" << dist.reshape(1, 1) << "R" << R << "t" << t;
      if (cam.image_width > 0) fs << "image_width" << cam.image_width << "image_height" << cam.image_height;
      fs << "}";
    };
    write_camera("frontal", rig.frontal);
    write_camera("lateral", rig.lateral);
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{}: {}", path.string(), e.err)};
  }
  return Ok{};
}

}  // namespace spinewatch
