// Speed of the accurate model: one incremental frame (step) and a full
// batch settle from the neutral posture (the paper: 88 s per deformation).
#include <benchmark/benchmark.h>

#include "spine_truth.hpp"
#include "spinewatch/estimator/load/ergonomics.hpp"
#include "spinewatch/estimator/load/schultz.hpp"
#include "spinewatch/estimator/spine/spine_dynamics.hpp"
#include "spinewatch/estimator/spine/stiffness_fit.hpp"
#include "spinewatch/estimator/spine/vertebra_geometry.hpp"

namespace spinewatch {
namespace {

const test::TruthSubject& subject() {
  static const test::TruthSubject s = test::make_subject(1600, 1.3);
  return s;
}
const SpineModel& model() {
  static const SpineModel m = SpineModel::from_subject(subject().spine);
  return m;
}

// One frame of a 3 s lateral bend at 30 frames/s (16 implicit substeps).
void BM_IncrementalStep(benchmark::State& state) {
  const auto truth = test::lateral_sequence(subject(), 90);
  std::vector<SpineTargets> targets;
  for (const auto& p : truth) targets.push_back(*targets_of(p));
  SpineDynamics dyn(model());
  std::size_t f = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(dyn.step(targets[f], 1.0 / 30));
    f = (f + 1) % targets.size();
  }
}
BENCHMARK(BM_IncrementalStep)->Unit(benchmark::kMicrosecond);

// The paper's batch process from the neutral posture to a bent one.
void BM_SettleFromNeutral(benchmark::State& state) {
  const double flexion = double(state.range(0)), lateral = double(state.range(1));
  const SpineTargets t = *targets_of(test::truth_posture(subject(), flexion, lateral, 0, 0));
  SpineDynamics dyn(model());
  int iterations = 0;
  for (auto _ : state) {
    dyn.reset(model().neutral());
    iterations = dyn.settle(t).iterations;
  }
  state.counters["rounds"] = iterations;
}
BENCHMARK(BM_SettleFromNeutral)->Args({0, 25})->Args({50, 0})->Unit(benchmark::kMillisecond);

void BM_LoadsAndErgonomics(benchmark::State& state) {
  const SpinePose pose = *test::truth_posture(subject(), 30, 10, 0, 0).vertebrae;
  ErgonomicsMonitor monitor(model().neutral());
  std::int64_t t = 0;
  for (auto _ : state) {
    const auto loads = compute_loads(pose, default_load_params());
    benchmark::DoNotOptimize(monitor.update(pose, loads, t += 33'333'333));
  }
}
BENCHMARK(BM_LoadsAndErgonomics)->Unit(benchmark::kMicrosecond);

// Building a subject's spine voxelises each vertebra (1 mm voxels): an L3
// sized lumbar vertebra with its processes, each primitive on its own
// bounds (Arg 0) against every voxel of the union's bounds tested against
// every primitive (Arg 1, the reference).
void BM_VoxeliseVertebra(benchmark::State& state) {
  const Solid solid = vertebra_solid(BodyDims{28, 50, 35}, generic_vertebra_geometry().lumbar);
  const bool reference = state.range(0) == 1;
  std::size_t voxels = 0;
  for (auto _ : state) {
    const auto points = reference ? voxelise_reference(solid, 1.0) : voxelise(solid, 1.0);
    voxels = points.size();
    benchmark::DoNotOptimize(points.data());
  }
  state.counters["voxels"] = static_cast<double>(voxels);
}
BENCHMARK(BM_VoxeliseVertebra)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The whole subject spine (17 vertebrae, their bodies, discs).
void BM_SpineModelFromSubject(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(SpineModel::from_subject(subject().spine));
}
BENCHMARK(BM_SpineModelFromSubject)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace spinewatch

BENCHMARK_MAIN();
