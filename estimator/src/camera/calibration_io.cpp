// calibration.yaml through cv::FileStorage, so that files written by
// OpenCV tools (and by us) read back exactly.
#include <algorithm>
#include <string_view>

#include <fmt/format.h>

#include <opencv2/core.hpp>
#include <Eigen/Dense>
#include <opencv2/core/eigen.hpp>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/frames/printable.hpp"
#include "spinewatch/frames/text_file.hpp"

namespace spinewatch {
namespace {

// OpenCV sizes a matrix from its header before it reads the data, so a
// corrupt header ("cols: 2147483647") would have it allocate gigabytes:
// the header is checked first. No matrix here has more than 9 elements.
Status check_matrix_header(const cv::FileNode& node, const std::string& where, const char* key) {
  constexpr int kMaxSide = 16;
  const auto small = [](const cv::FileNode& n) { return n.isInt() && int(n) >= 1 && int(n) <= kMaxSide; };
  const auto bad = [&] {
    return Error{fmt::format("{}.{}: not a matrix (rows and cols must be integers 1..{})", where, key, kMaxSide)};
  };
  if (!node.isMap()) return Error{fmt::format("{}.{}: not a matrix", where, key)};
  if (const cv::FileNode sizes = node["sizes"]; !sizes.empty()) {  // opencv-nd-matrix
    if (!sizes.isSeq() || sizes.size() < 1 || sizes.size() > 2) return bad();
    for (const cv::FileNode& side : sizes)
      if (!small(side)) return bad();
    return Ok{};
  }
  if (!small(node["rows"]) || !small(node["cols"])) return bad();
  return Ok{};
}

Result<cv::Mat> read_matrix(const cv::FileNode& camera, const std::string& where, const char* key,
                            int rows, int cols) {
  const cv::FileNode node = camera[key];
  if (node.empty()) return Error{fmt::format("{}.{}: missing", where, key)};
  if (auto header = check_matrix_header(node, where, key); !header) return header.error();
  cv::Mat m;
  try {
    node >> m;
  } catch (const std::exception&) {  // cv::Exception, or a standard one from OpenCV's reader
    return Error{fmt::format("{}.{}: not a matrix", where, key)};
  }
  if (m.empty()) return Error{fmt::format("{}.{}: not a matrix", where, key)};
  if (m.rows * m.cols == rows * cols && (m.rows == 1 || m.cols == 1) && (rows == 1 || cols == 1))
    m = m.reshape(1, rows);
  if (m.rows != rows || m.cols != cols)
    return Error{fmt::format("{}.{}: expected {}x{}, got {}x{}", where, key, rows, cols, m.rows, m.cols)};
  m.convertTo(m, CV_64F);
  for (int i = 0; i < m.rows * m.cols; ++i)
    if (!std::isfinite(m.at<double>(i)))
      return Error{fmt::format("{}.{}: element {} is not finite", where, key, i)};
  return m;
}

Result<CameraModel> read_camera(const cv::FileStorage& fs, const std::string& file, const char* name) {
  const cv::FileNode node = fs[name];
  const std::string where = fmt::format("{}: {}", file, name);
  if (node.empty() || !node.isMap()) return Error{fmt::format("{}: missing camera node", where)};
  auto K = read_matrix(node, where, "camera_matrix", 3, 3);
  if (!K) return K.error();
  auto dist = read_matrix(node, where, "dist_coeffs", 1, 5);
  if (!dist) return dist.error();
  auto R = read_matrix(node, where, "R", 3, 3);
  if (!R) return R.error();
  auto t = read_matrix(node, where, "t", 3, 1);
  if (!t) return t.error();

  CameraModel cam;
  cv::cv2eigen(*K, cam.camera_matrix);
  for (int i = 0; i < 5; ++i) cam.dist_coeffs[static_cast<std::size_t>(i)] = dist->at<double>(i);
  cv::cv2eigen(*R, cam.R);
  cv::cv2eigen(*t, cam.t);
  if (cam.camera_matrix(0, 0) <= 0 || cam.camera_matrix(1, 1) <= 0)
    return Error{fmt::format("{}.camera_matrix: focal lengths must be positive", where)};
  const double orthonormality = (cam.R * cam.R.transpose() - Eigen::Matrix3d::Identity()).norm();
  if (orthonormality > 1e-3 || cam.R.determinant() < 0)
    return Error{fmt::format("{}.R: not a rotation matrix (|R·Rᵀ − I| = {:.3g}, det = {:.3g})", where,
                             orthonormality, cam.R.determinant())};
  return cam;
}

// What OpenCV 4.6 cannot be trusted to read, refused before it sees the
// file. Its YAML reader never returns on some malformed files (the
// calibration_yaml fuzzer found "%YAML:1.0\n-----0\n-\n" and
// "%YAML:1.0\n a: o\nf---\n"): a line holding "---" other than the
// document marker alone is refused before OpenCV sees it (OpenCV writes
// "---" alone, and no value of a calibration holds it). Other loops in
// OpenCV's reader may remain: docs/testing.md, "Fuzzing".
Status check_before_opencv(const std::string& text, const std::string& file) {
  // calibration.yaml is FileStorage YAML (interfaces.md §2). OpenCV would
  // also parse XML or JSON by the first character, and its 4.6 XML reader
  // dereferences null on a header as short as "<?xml e=" (found by the
  // calibration_yaml fuzzer): those are refused, as is a NUL byte.
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && (text[first] == '<' || text[first] == '{'))
    return Error{fmt::format("{}: XML or JSON storage; calibration.yaml is read as YAML only", file)};
  if (text.find('\0') != std::string::npos) return Error{fmt::format("{}: a NUL byte: not a text file", file)};
  std::size_t line = 1;
  for (std::size_t at = 0; at < text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view l(text.data() + at, end - at);
    const std::string_view trimmed = l.substr(0, l.find_last_not_of(" \t\r") + 1);
    if (l.find("---") != std::string_view::npos && trimmed != "---")
      return Error{fmt::format("{}: line {}: \"{}\": \"---\" only as a document marker on a line of its own", file,
                               line, printable(l.substr(0, 16)))};
    at = end + 1;
  }
  return Ok{};
}

}  // namespace

Result<CameraRig> load_calibration(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) return Error{fmt::format("{}: no such file", file)};
  auto text = read_text_file(path);
  if (!text) return text.error();
  if (auto checked = check_before_opencv(*text, file); !checked) return checked.error();
  // Everything OpenCV does with the file is inside the try: its reader
  // throws cv::Exception from places a caller would not expect (indexing a
  // root that is not a map) and lets standard exceptions through
  // (std::length_error) — both found by the calibration_yaml fuzzer
  // (tests/fuzz), both ended the program before.
  try {
    cv::FileStorage fs;
    if (!fs.open(file, cv::FileStorage::READ)) return Error{fmt::format("{}: cannot be read", file)};
    if (!fs.root().isMap())
      return Error{fmt::format("{}: expected a map with the nodes frontal and lateral", file)};
    auto frontal = read_camera(fs, file, "frontal");
    if (!frontal) return frontal.error();
    auto lateral = read_camera(fs, file, "lateral");
    if (!lateral) return lateral.error();
    return CameraRig{*frontal, *lateral};
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{}: not an OpenCV FileStorage file ({})", file, printable(e.err))};
  } catch (const std::exception& e) {
    return Error{fmt::format("{}: not an OpenCV FileStorage file ({})", file, printable(e.what()))};
  }
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
      cv::Mat dist(1, 5, CV_64F);
      for (int i = 0; i < 5; ++i) dist.at<double>(i) = cam.dist_coeffs[static_cast<std::size_t>(i)];
      fs << name << "{" << "camera_matrix" << K << "dist_coeffs" << dist << "R" << R << "t" << t << "}";
    };
    write_camera("frontal", rig.frontal);
    write_camera("lateral", rig.lateral);
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{}: {}", path.string(), e.err)};
  }
  return Ok{};
}

}  // namespace spinewatch
