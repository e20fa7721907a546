// Time of one BlazePose landmark inference (256×256 RGB crop → landmarks,
// presence, mask) by Arm NN on its reference CPU backend, one thread, for
// each of the three models @mediapipe/pose ships. The reference backend's
// time does not depend on the image, so the input is a fixed gradient.
// The models come from scripts/install-deps (model_dir.hpp); a missing one
// is reported as a skipped benchmark. Each repetition is one inference; the
// median of the ten is the figure (docs/cvsm.md): on the shared VM single
// runs vary by ±30 %.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "spinewatch/landmarks/model_dir.hpp"
#include "spinewatch/landmarks/pose_landmarker.hpp"

namespace lm = spinewatch::landmarks;

namespace {

std::vector<float> gradient_input() {
  std::vector<float> rgb(static_cast<std::size_t>(lm::kInputSide) * lm::kInputSide * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<float>(i % 251) / 250.0f;
  return rgb;
}

void BM_PoseLandmarkCpuRef(benchmark::State& state, const std::string& model) {
  const std::string path = lm::mediapipe_dir() + "/pose_landmark_" + model + ".tflite";
  if (!std::filesystem::exists(path)) {
    state.SkipWithError((path + " is absent (scripts/install-deps)").c_str());
    return;
  }
  lm::PoseLandmarker landmarker(path, {"CpuRef"});
  const auto input = gradient_input();
  for (auto _ : state) benchmark::DoNotOptimize(landmarker.infer(input));
}

}  // namespace

BENCHMARK_CAPTURE(BM_PoseLandmarkCpuRef, lite, std::string("lite"))
    ->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(10)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_PoseLandmarkCpuRef, full, std::string("full"))
    ->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(10)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_PoseLandmarkCpuRef, heavy, std::string("heavy"))
    ->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(10)->ReportAggregatesOnly(true);

BENCHMARK_MAIN();
