// A measurement, not a test: two cameras of a caliscope session
// (../shared/data/real/caliscope/, synchronised 1280×720 videos of a
// hand-held inverted 4 × 5 ChArUco board), each camera's intrinsics fitted
// from its own video by several ways of choosing the views and several
// lens models, the rig then fitted to the shared frames with those
// intrinsics held (as calibrate does), and the rig set beside caliscope's
// camera_array.toml. Usage: caliscope_method SESSION_DIR FRONTAL_ID LATERAL_ID.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <set>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <toml++/toml.h>

#include "spinewatch/estimator/calibration/board.hpp"

using namespace spinewatch;

namespace {

struct Seen {
  int frame = 0;
  std::vector<int> ids;
  std::vector<cv::Point2f> pixels;
};

struct Camera {
  cv::Matx33d K;
  cv::Mat dist;
  cv::Matx33d R;  // world → camera
  cv::Vec3d t;    // mm
  double rms = 0;
  int views = 0;
};

std::vector<std::optional<Seen>> detect_all(const CalibrationBoard& board, const std::filesystem::path& video) {
  std::vector<std::optional<Seen>> out;
  cv::VideoCapture capture(video.string());
  cv::Mat frame, grey;
  bool inverted = true;
  while (capture.read(frame)) {
    cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
    BoardDetection d = board.detect(grey, inverted);
    if (!d.empty()) inverted = d.inverted;
    if (board.usable(d, 4))
      out.push_back(Seen{int(out.size()), d.ids, d.pixels});
    else
      out.push_back(std::nullopt);
  }
  return out;
}

Camera caliscope_camera(const toml::table& array, int id) {
  const toml::node_view<const toml::node> cam = array["cameras"][std::to_string(id)];
  Camera c;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) {
      c.K(r, k) = cam["matrix"][r][k].value_or(0.0);
      c.R(r, k) = cam["rotation"][r][k].value_or(0.0);
    }
  for (int k = 0; k < 3; ++k) c.t[k] = 1000 * cam["translation"][k].value_or(0.0);
  c.dist = cv::Mat(1, 5, CV_64F);
  for (int k = 0; k < 5; ++k) c.dist.at<double>(k) = cam["distortions"][k].value_or(0.0);
  return c;
}

// A homography from the board's plane (its corners scaled to the unit
// square) to the image; its perspective row says which way and how much
// the board leans away from facing the camera.
struct Lean {
  double direction = 0;  // rad, [0, 2π)
  double magnitude = 0;
};
Lean lean_of(const CalibrationBoard& board, const Seen& s) {
  std::vector<cv::Point2f> plane;
  cv::Point2f lo{1e9f, 1e9f}, hi{-1e9f, -1e9f};
  for (int id : s.ids) {
    const cv::Point3f& c = board.corner(id);
    lo = {std::min(lo.x, c.x), std::min(lo.y, c.y)};
    hi = {std::max(hi.x, c.x), std::max(hi.y, c.y)};
  }
  for (int id : s.ids) {
    const cv::Point3f& c = board.corner(id);
    plane.push_back({(c.x - lo.x) / std::max(hi.x - lo.x, 1e-6f), (c.y - lo.y) / std::max(hi.y - lo.y, 1e-6f)});
  }
  cv::Mat H = cv::findHomography(plane, s.pixels, cv::RANSAC, 5.0);
  if (H.empty()) return {};
  H /= H.at<double>(2, 2);
  const double gx = H.at<double>(2, 0), gy = H.at<double>(2, 1);
  double direction = std::atan2(gy, gx);
  if (direction < 0) direction += 2 * std::numbers::pi;
  return {direction, std::hypot(gx, gy)};
}

std::set<std::pair<int, int>> cells_of(const Seen& s, cv::Size size, int grid) {
  std::set<std::pair<int, int>> cells;
  for (const auto& p : s.pixels)
    cells.insert({std::clamp(int(p.y * grid / size.height), 0, grid - 1),
                  std::clamp(int(p.x * grid / size.width), 0, grid - 1)});
  return cells;
}

// caliscope's current selection (frame_selector.py, as its docs and code
// describe it): frames with 6 corners or more; first the most leaning
// frame of each of 8 lean directions, then frames chosen one at a time for
// the 5 × 5 cells of the image they add (edge and corner cells counting
// more) and for how far their position and spread lie from those chosen;
// 30 at most.
std::vector<Seen> select_spread(const CalibrationBoard& board, const std::vector<Seen>& eligible, cv::Size size) {
  const int grid = 5;
  std::map<int, std::pair<double, std::size_t>> best_of_bin;
  for (std::size_t i = 0; i < eligible.size(); ++i) {
    const Lean l = lean_of(board, eligible[i]);
    if (l.magnitude < 0.1) continue;
    const int bin = std::min(int(l.direction / (2 * std::numbers::pi) * 8), 7);
    auto it = best_of_bin.find(bin);
    if (it == best_of_bin.end() || l.magnitude > it->second.first) best_of_bin[bin] = {l.magnitude, i};
  }
  std::vector<std::size_t> chosen;
  for (const auto& [bin, best] : best_of_bin) chosen.push_back(best.second);
  auto features = [&](const Seen& s) {
    cv::Scalar mean, sd;
    cv::meanStdDev(s.pixels, mean, sd);
    const double sx = sd[0] / size.width, sy = sd[1] / size.height;
    return cv::Vec<double, 5>(mean[0] / size.width, mean[1] / size.height, sx, sy, sy > 1e-6 ? sx / sy : 1.0);
  };
  std::set<std::pair<int, int>> covered;
  for (std::size_t i : chosen) {
    auto c = cells_of(eligible[i], size, grid);
    covered.insert(c.begin(), c.end());
  }
  while (chosen.size() < 30) {
    double best = -1;
    std::size_t pick = 0;
    for (std::size_t i = 0; i < eligible.size(); ++i) {
      if (std::find(chosen.begin(), chosen.end(), i) != chosen.end()) continue;
      double score = 0;
      for (const auto& cell : cells_of(eligible[i], size, grid)) {
        if (covered.count(cell)) continue;
        const bool edge_row = cell.first == 0 || cell.first == grid - 1;
        const bool edge_col = cell.second == 0 || cell.second == grid - 1;
        score += 1 + ((edge_row || edge_col) ? 0.2 : 0) + ((edge_row && edge_col) ? 0.3 : 0);
      }
      double nearest = 1e9;
      for (std::size_t j : chosen) nearest = std::min(nearest, cv::norm(features(eligible[i]) - features(eligible[j])));
      if (!chosen.empty()) score += 0.3 * nearest;
      if (score > best) {
        best = score;
        pick = i;
      }
    }
    if (best < 0.01) break;
    chosen.push_back(pick);
    auto c = cells_of(eligible[pick], size, grid);
    covered.insert(c.begin(), c.end());
  }
  std::vector<Seen> out;
  for (std::size_t i : chosen) out.push_back(eligible[i]);
  return out;
}

// cv::calibrateCamera over the views. `guess`: start from f = the image's
// larger side and the centre at `centre` (the image's middle when not
// given), as caliscope does today; with CALIB_FIX_PRINCIPAL_POINT in
// `flags` the centre stays there.
Camera fit(const CalibrationBoard& board, const std::vector<Seen>& views, cv::Size size, int flags, bool guess,
           std::optional<cv::Point2d> centre = std::nullopt) {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  for (const auto& v : views) {
    object.push_back(board.object_points(v.ids));
    image.push_back(v.pixels);
  }
  Camera c;
  cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
  if (guess) {
    K.at<double>(0, 0) = K.at<double>(1, 1) = std::max(size.width, size.height);
    K.at<double>(0, 2) = centre ? centre->x : (size.width - 1) * 0.5;
    K.at<double>(1, 2) = centre ? centre->y : (size.height - 1) * 0.5;
    flags |= cv::CALIB_USE_INTRINSIC_GUESS;
  }
  cv::Mat dist = cv::Mat::zeros(1, 5, CV_64F);
  std::vector<cv::Mat> rvecs, tvecs;
  c.rms = cv::calibrateCamera(object, image, size, K, dist, rvecs, tvecs, flags,
                              cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
  c.K = K;
  c.dist = dist;
  c.views = int(views.size());
  return c;
}

// RMS reprojection error (px) of the views through the given intrinsics,
// each view's board pose fitted to it (solvePnP).
double views_rms(const CalibrationBoard& board, const std::vector<Seen>& views, const Camera& c) {
  double sum = 0;
  std::size_t n = 0;
  for (const auto& v : views) {
    const std::vector<cv::Point3f> object = board.object_points(v.ids);
    cv::Mat rvec, tvec;
    cv::solvePnP(object, v.pixels, cv::Mat(c.K), c.dist, rvec, tvec);
    cv::solvePnPRefineLM(object, v.pixels, cv::Mat(c.K), c.dist, rvec, tvec);
    std::vector<cv::Point2f> projected;
    cv::projectPoints(object, rvec, tvec, cv::Mat(c.K), c.dist, projected);
    for (std::size_t i = 0; i < projected.size(); ++i) {
      const cv::Point2f d = projected[i] - v.pixels[i];
      sum += d.dot(d);
    }
    n += projected.size();
  }
  return n ? std::sqrt(sum / double(n)) : 0;
}

double angle_deg(const cv::Matx33d& a, const cv::Matx33d& b) {
  const cv::Matx33d d = a * b.t();
  return std::acos(std::clamp((cv::trace(d) - 1) / 2, -1.0, 1.0)) * 180 / std::numbers::pi;
}

struct Rig {
  cv::Matx33d R;
  cv::Vec3d t;
  double rms = 0;
  int frames = 0;
};

// The lateral camera from the frontal over every frame both saw 6 or more
// of the same corners in, the intrinsics held.
Rig fit_rig(const CalibrationBoard& board, const std::vector<std::optional<Seen>>& a,
            const std::vector<std::optional<Seen>>& b, const Camera& ca, const Camera& cb, cv::Size size) {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> pa, pb;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (!a[i] || !b[i]) continue;
    std::map<int, cv::Point2f> at;
    for (std::size_t k = 0; k < b[i]->ids.size(); ++k) at[b[i]->ids[k]] = b[i]->pixels[k];
    std::vector<int> ids;
    std::vector<cv::Point2f> xa, xb;
    for (std::size_t k = 0; k < a[i]->ids.size(); ++k)
      if (auto it = at.find(a[i]->ids[k]); it != at.end()) {
        ids.push_back(a[i]->ids[k]);
        xa.push_back(a[i]->pixels[k]);
        xb.push_back(it->second);
      }
    if (ids.size() < 6) continue;
    object.push_back(board.object_points(ids));
    pa.push_back(xa);
    pb.push_back(xb);
  }
  Rig rig;
  cv::Mat Ka(ca.K), Kb(cb.K), da = ca.dist.clone(), db = cb.dist.clone(), R, t, E, F;
  rig.rms = cv::stereoCalibrate(object, pa, pb, Ka, da, Kb, db, size, R, t, E, F, cv::CALIB_FIX_INTRINSIC,
                                cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
  rig.R = R;
  rig.t = t;
  rig.frames = int(object.size());
  return rig;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: caliscope_method SESSION_DIR FRONTAL_ID LATERAL_ID\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  const int ids[2] = {std::atoi(argv[2]), std::atoi(argv[3])};
  BoardSpec spec{BoardKind::Charuco, 4, 5, 54, 40.5, "DICT_4X4_1000", false};
  auto board = CalibrationBoard::create(spec);
  if (!board) return 1;
  const cv::Size size{1280, 720};
  const toml::table array = toml::parse_file((dir / "camera_array.toml").string());
  Camera reference[2] = {caliscope_camera(array, ids[0]), caliscope_camera(array, ids[1])};
  const cv::Matx33d ref_R = reference[1].R * reference[0].R.t();
  const cv::Vec3d ref_t = reference[1].t - ref_R * reference[0].t;

  std::vector<std::optional<Seen>> seen[2];
  for (int c = 0; c < 2; ++c) seen[c] = detect_all(*board, dir / ("cam_" + std::to_string(ids[c]) + ".mp4"));

  struct Method {
    std::string name;
    std::function<std::vector<Seen>(const std::vector<std::optional<Seen>>&)> views;
    int flags;
    bool guess;
  };
  auto with_at_least = [](int n) {
    return [n](const std::vector<std::optional<Seen>>& all) {
      std::vector<Seen> out;
      for (const auto& s : all)
        if (s && int(s->ids.size()) >= n) out.push_back(*s);
      return out;
    };
  };
  // caliscope 2023 (pyxy3d's MonoCalibrator): a view kept when more than
  // 70 % of the board's corners are found and half a second has passed
  // since the last one kept (3 frames at 6 fps).
  auto spaced_most = [&](const std::vector<std::optional<Seen>>& all) {
    std::vector<Seen> out;
    int last = -1000;
    for (const auto& s : all)
      if (s && double(s->ids.size()) > 0.7 * board->corner_count() && s->frame - last >= 3) {
        out.push_back(*s);
        last = s->frame;
      }
    return out;
  };
  auto spread = [&](const std::vector<std::optional<Seen>>& all) {
    return select_spread(*board, with_at_least(6)(all), size);
  };
  const std::vector<Method> methods = {
      {"every frame >= 8 corners, k3 = 0", with_at_least(8), cv::CALIB_FIX_K3, false},
      {"every frame >= 8 corners, k1 k2 p1 p2 k3", with_at_least(8), 0, false},
      {"every frame >= 8 corners, k1 k2 only", with_at_least(8), cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST, false},
      {"every frame >= 6 corners, k3 = 0", with_at_least(6), cv::CALIB_FIX_K3, false},
      {"caliscope 2023: > 70 % of corners, 0.5 s apart, 5 terms", spaced_most, 0, false},
      {"caliscope 2023 selection, k3 = 0", spaced_most, cv::CALIB_FIX_K3, false},
      {"caliscope today: 30 frames spread, 5 terms", spread, 0, true},
      {"caliscope today selection, k3 = 0", spread, cv::CALIB_FIX_K3, true},
  };
  std::printf("session %s, cam_%d frontal, cam_%d lateral; caliscope: rotation %.2f°, baseline %.1f mm\n",
              dir.filename().c_str(), ids[0], ids[1],
              std::acos(std::clamp((cv::trace(ref_R) - 1) / 2, -1.0, 1.0)) * 180 / std::numbers::pi,
              cv::norm(ref_t));
  for (int c = 0; c < 2; ++c)
    std::printf("  caliscope cam_%d: fx %.1f fy %.1f cx %.1f cy %.1f\n", ids[c], reference[c].K(0, 0),
                reference[c].K(1, 1), reference[c].K(0, 2), reference[c].K(1, 2));
  for (int c = 0; c < 2; ++c) {
    int any = 0, eight = 0, most = 0;
    for (const auto& s : seen[c]) {
      if (!s) continue;
      ++any;
      eight += s->ids.size() >= 8;
      most += double(s->ids.size()) > 0.7 * board->corner_count();
    }
    std::printf("  cam_%d: %zu frames, the board (4+ corners) in %d, 8+ corners in %d, over 70 %% of them in %d\n", ids[c],
                seen[c].size(), any, eight, most);
  }
  auto print = [&](const std::string& name, const Camera cams[2]) {
    const Rig rig = fit_rig(*board, seen[0], seen[1], cams[0], cams[1], size);
    std::printf("%-58s rot %5.2f° base %+6.1f mm (%d shared, %.2f px)\n", name.c_str(), angle_deg(rig.R, ref_R),
                cv::norm(rig.t) - cv::norm(ref_t), rig.frames, rig.rms);
    for (int c = 0; c < 2; ++c)
      std::printf("    cam_%d %2d views %.2f px: fx %6.1f fy %6.1f cx %6.1f cy %6.1f k %+.3f %+.3f %+.4f %+.4f %+.3f\n",
                  ids[c], cams[c].views, cams[c].rms, cams[c].K(0, 0), cams[c].K(1, 1), cams[c].K(0, 2),
                  cams[c].K(1, 2), cams[c].dist.at<double>(0), cams[c].dist.at<double>(1), cams[c].dist.at<double>(2),
                  cams[c].dist.at<double>(3), cams[c].dist.total() > 4 ? cams[c].dist.at<double>(4) : 0.0);
  };
  print("caliscope's intrinsics", reference);
  for (int c = 0; c < 2; ++c) {
    const std::vector<Seen> views = methods[0].views(seen[c]);
    const Camera own = fit(*board, views, size, methods[0].flags, false);
    std::printf("    cam_%d's %zu views (8+ corners), each pose fitted: %.3f px through caliscope's intrinsics, %.3f px "
                "through their own fit (k3 = 0)\n",
                ids[c], views.size(), views_rms(*board, views, reference[c]), views_rms(*board, views, own));
  }
  for (const Method& m : methods) {
    Camera cams[2];
    for (int c = 0; c < 2; ++c) cams[c] = fit(*board, m.views(seen[c]), size, m.flags, m.guess);
    print(m.name, cams);
  }
  // The principal points alone: each camera's views with k3 = 0 (the first
  // method), the centres held where given.
  const std::vector<Seen> views[2] = {methods[0].views(seen[0]), methods[0].views(seen[1])};
  const Camera own[2] = {fit(*board, views[0], size, cv::CALIB_FIX_K3, false),
                         fit(*board, views[1], size, cv::CALIB_FIX_K3, false)};
  const int held = cv::CALIB_FIX_K3 | cv::CALIB_FIX_PRINCIPAL_POINT;
  auto centre_of = [](const Camera& c) { return cv::Point2d(c.K(0, 2), c.K(1, 2)); };
  const cv::Point2d middle((size.width - 1) * 0.5, (size.height - 1) * 0.5);
  {
    const Camera cams[2] = {reference[0], own[1]};
    print("caliscope's intrinsics for the frontal camera only", cams);
  }
  {
    const Camera cams[2] = {own[0], reference[1]};
    print("caliscope's intrinsics for the lateral camera only", cams);
  }
  {
    const Camera cams[2] = {fit(*board, views[0], size, held, true, centre_of(reference[0])),
                            fit(*board, views[1], size, held, true, centre_of(reference[1]))};
    print("both centres held at caliscope's, the rest fitted", cams);
  }
  {
    const Camera cams[2] = {fit(*board, views[0], size, held, true, middle),
                            fit(*board, views[1], size, held, true, middle)};
    print("both centres held at the image's middle", cams);
  }
  return 0;
}
