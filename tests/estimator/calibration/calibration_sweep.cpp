// A measurement, not a test: calibrate_station on board sessions rendered
// with the seeds and noise given (not the one calibration_test asserts on),
// printing each camera's errors against the truth and its principal point
// and focal length errors. Usage: calibration_sweep SEEDS [NOISE [VIEWS_PER_CAMERA]].
// calibration_sweep --perturb DIR: the default rig and perturbed copies.
// calibration_sweep --recover DIR SEED VIEWS_PER_CAMERA: the default rig as
// calibrate_station recovers it from a session rendered with that seed
// (noise 2.0, as CalibrateCli's), into DIR/recovered_SEED_VIEWS.yaml: the
// replay comparison of docs/calibration.md with more or fewer poses.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "spinewatch/estimator/calibration/station_calibration.hpp"
#include "spinewatch/phantom/board_views.hpp"
#include "station_rig.hpp"

using namespace spinewatch;

static double rot_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const double c = std::clamp(((a * b.transpose()).trace() - 1) / 2, -1.0, 1.0);
  return std::acos(c) * 180 / std::numbers::pi;
}

// The default rig and copies of it each perturbed by one small change, as
// calibration.yaml files into `dir`: what replay's postures do with a
// calibration 0.1 px or 0.1° off (docs/calibration.md, "How it is tested").
int perturb(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const CameraRig truth = CameraRig::default_rig();
  auto write = [&](const std::string& name, const CameraRig& rig) {
    if (!save_calibration(dir / (name + ".yaml"), rig)) std::printf("cannot write %s\n", name.c_str());
  };
  write("truth", truth);
  auto turned = [](CameraModel cam, const Eigen::Vector3d& axis, double deg) {
    // About the camera's own centre: the centre stays, the aim turns.
    const Eigen::Vector3d c = cam.centre_in_world();
    cam.R = Eigen::AngleAxisd(deg * std::numbers::pi / 180, axis).toRotationMatrix() * cam.R;
    cam.t = -cam.R * c;
    return cam;
  };
  for (int v = 0; v < 2; ++v) {
    const char* n = v ? "lateral" : "frontal";
    for (double px : {0.01, 0.1, 0.3}) {
      CameraRig r = truth;
      (v ? r.lateral : r.frontal).camera_matrix(0, 2) += px;
      write(fmt::format("{}_cx+{}px", n, px), r);
      r = truth;
      (v ? r.lateral : r.frontal).camera_matrix(1, 2) += px;
      write(fmt::format("{}_cy+{}px", n, px), r);
    }
    for (double deg : {0.1, 0.3}) {
      CameraRig r = truth;
      (v ? r.lateral : r.frontal) = turned(v ? r.lateral : r.frontal, Eigen::Vector3d::UnitY(), deg);
      write(fmt::format("{}_pan+{}deg", n, deg), r);
      r = truth;
      (v ? r.lateral : r.frontal) = turned(v ? r.lateral : r.frontal, Eigen::Vector3d::UnitX(), deg);
      write(fmt::format("{}_tilt+{}deg", n, deg), r);
    }
  }
  return 0;
}

int recover(const std::filesystem::path& dir, std::uint32_t seed, int views_per_camera) {
  const CameraRig rig = CameraRig::default_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  phantom::BoardSessionOptions o;
  o.views_per_camera = views_per_camera;
  o.seed = seed;
  const auto plan = phantom::plan_board_session(rig, board, o);
  const auto views = phantom::render_board_views(rig, board, plan.views, {true, true}, seed, 2.0);
  const auto placed = phantom::render_board_views(rig, board, std::vector<phantom::BoardPose>(4, plan.placement),
                                                  {true, true}, seed, 2.0, 1000);
  std::array<CameraFrames, 2> frames;
  for (int v = 0; v < 2; ++v) {
    frames[v].views = views.grey[v];
    frames[v].placement = placed.grey[v];
  }
  const auto r = calibrate_station(board, frames, {320, 240}, {Placement::Upright, 1100}, {});
  std::filesystem::create_directories(dir);
  const auto file = dir / fmt::format("recovered_{}_{}.yaml", seed, views_per_camera);
  if (!save_calibration(file, r.rig)) {
    std::printf("cannot write %s\n", file.c_str());
    return 1;
  }
  for (int i = 0; i < 2; ++i)
    std::printf("%s: rms %.3f px\n", i ? "lateral" : "frontal", r.report.cameras[static_cast<std::size_t>(i)].rms_px);
  return 0;
}

int main(int argc, char** argv) {
  if (argc > 2 && std::string(argv[1]) == "--perturb") return perturb(argv[2]);
  if (argc > 4 && std::string(argv[1]) == "--recover")
    return recover(argv[2], static_cast<std::uint32_t>(std::stoul(argv[3])), std::atoi(argv[4]));
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  const double noise = argc > 2 ? atof(argv[2]) : 2.0;
  std::stringstream seeds(argc > 1 ? argv[1] : "2,3,4");
  for (std::string tok; std::getline(seeds, tok, ',');) {
    phantom::BoardSessionOptions o;
    o.views_per_camera = argc > 3 ? atoi(argv[3]) : 40;
    o.seed = std::uint32_t(std::stoul(tok));
    o.noise_sigma = noise;
    const auto plan = phantom::plan_board_session(rig, board, o);
    const auto views = phantom::render_board_views(rig, board, plan.views, {true, true}, o.seed, o.noise_sigma);
    const std::vector<phantom::BoardPose> still(4, plan.placement);
    const auto placed = phantom::render_board_views(rig, board, still, {true, true}, o.seed, o.noise_sigma, 1000);
    std::array<CameraFrames, 2> frames;
    for (int v = 0; v < 2; ++v) {
      frames[v].views = views.grey[v];
      frames[v].placement = placed.grey[v];
    }
    const auto r = calibrate_station(board, frames, {320, 240}, {Placement::Upright, 1100}, {});
    const CameraModel* t[2] = {&rig.frontal, &rig.lateral};
    const CameraModel* c[2] = {&r.rig.frontal, &r.rig.lateral};
    for (int i = 0; i < 2; ++i)
      std::printf("seed %s %s: rot %.3f deg centre %.2f mm  cx %+.2f cy %+.2f fx %+.2f fy %+.2f rms %.3f\n",
                  tok.c_str(), i ? "lateral" : "frontal", rot_deg(t[i]->R, c[i]->R),
                  (t[i]->centre_in_world() - c[i]->centre_in_world()).norm(),
                  c[i]->camera_matrix(0, 2) - t[i]->camera_matrix(0, 2),
                  c[i]->camera_matrix(1, 2) - t[i]->camera_matrix(1, 2),
                  c[i]->camera_matrix(0, 0) - t[i]->camera_matrix(0, 0),
                  c[i]->camera_matrix(1, 1) - t[i]->camera_matrix(1, 1), r.report.cameras[i].rms_px);
    std::fflush(stdout);
  }
}
