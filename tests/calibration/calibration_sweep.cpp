// A measurement, not a test: calibrate_station on board sessions rendered
// with the seeds and noise given (not the one calibration_test asserts on),
// printing each camera's errors against the truth and its principal point
// and focal length errors. Usage: calibration_sweep SEEDS [NOISE].
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <sstream>

#include "spinewatch/estimator/calibration/station_calibration.hpp"
#include "spinewatch/phantom/board_views.hpp"
#include "station_rig.hpp"

using namespace spinewatch;

static double rot_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const double c = std::clamp(((a * b.transpose()).trace() - 1) / 2, -1.0, 1.0);
  return std::acos(c) * 180 / std::numbers::pi;
}

int main(int argc, char** argv) {
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  const double noise = argc > 2 ? atof(argv[2]) : 2.0;
  std::stringstream seeds(argc > 1 ? argv[1] : "2,3,4");
  for (std::string tok; std::getline(seeds, tok, ',');) {
    phantom::BoardSessionOptions o;
    o.views_per_camera = 40;
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
