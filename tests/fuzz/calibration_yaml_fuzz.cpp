// calibration.yaml (docs/calibration.md) through its public loader,
// load_calibration(path): the input is the file. Loaded cameras must hold
// what the loader promises (positive focal lengths, rotations, finite).
#include "fuzz_support.hpp"
#include "spinewatch/estimator/camera_model.hpp"

namespace {
namespace fs = std::filesystem;
using namespace spinewatch;

void check_camera(const CameraModel& cam) {
  FUZZ_CHECK(cam.camera_matrix.allFinite() && cam.R.allFinite() && cam.t.allFinite(), "a non-finite figure");
  FUZZ_CHECK(cam.camera_matrix(0, 0) > 0 && cam.camera_matrix(1, 1) > 0, "a focal length <= 0");
  FUZZ_CHECK((cam.R * cam.R.transpose() - Eigen::Matrix3d::Identity()).norm() <= 1e-3, "R is not a rotation");
  FUZZ_CHECK(cam.R.determinant() > 0, "R is a reflection");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::silence_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const fs::path file = fuzz::scratch_dir() / "calibration.yaml";
  fuzz::write_input(file, data, size);
  auto rig = load_calibration(file);
  if (!rig) {
    fuzz::check_one_clear_message(rig.error().message, file.string());
    return 0;
  }
  check_camera(rig->frontal);
  check_camera(rig->lateral);
  return 0;
}
