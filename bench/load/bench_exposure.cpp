// Cost per posture of what the daemon's estimator thread adds to every
// pair for exposure (docs/exposure.md): the summaries' accumulation and the
// alert rules. Both are checked against hand-computed sequences and the
// phantom's true spine in tests/estimator/load (exposure_test, alerts_test,
// exposure_phantom_test).
#include <benchmark/benchmark.h>

#include <cmath>

#include "spinewatch/estimator/load/alerts.hpp"
#include "spinewatch/estimator/load/exposure_accumulator.hpp"

namespace spinewatch {
namespace {

// A minute of postures at 30 fps bending, twisting and loading, with
// loads at every level as the estimator gives them.
std::vector<Posture> minute_of_postures() {
  std::vector<Posture> out;
  for (int i = 0; i < 1800; ++i) {
    Posture p;
    p.seq = std::uint64_t(i);
    p.t_ns = std::int64_t(i) * 33'333'333;
    p.state = TrackingState::Tracking;
    Ergonomics e;
    e.trunk_inclination_deg = 35 + 35 * std::sin(i * 0.01);
    e.lateral_bend_deg = 12 * std::sin(i * 0.05);
    e.twist_deg = 12 * std::cos(i * 0.03);
    e.reba_trunk = reba_trunk_score({e.trunk_inclination_deg, e.lateral_bend_deg, e.twist_deg}, default_ergonomic_limits());
    p.ergonomics = e;
    for (std::size_t k = 0; k < kVertebraCount; ++k)
      p.loads.push_back({std::string(kVertebraNames[k]), 600 + 150.0 * double(k) + 40 * e.trunk_inclination_deg});
    out.push_back(std::move(p));
  }
  return out;
}

void BM_ExposureAccumulatorAdd(benchmark::State& state) {
  const auto postures = minute_of_postures();
  ExposureOptions o;
  o.interval_ns = 10'000'000'000;  // an interval closes every 300 postures
  ExposureAccumulator acc(o);
  std::size_t i = 0;
  std::int64_t lap = 0;
  for (auto _ : state) {
    Posture p = postures[i];
    p.t_ns += lap;
    benchmark::DoNotOptimize(acc.add(p));
    if (++i == postures.size()) {
      i = 0;
      lap += 60'000'000'000;
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ExposureAccumulatorAdd);

void BM_AlertMonitorBuiltInRules(benchmark::State& state) {
  const auto postures = minute_of_postures();
  AlertMonitor monitor(builtin_alert_rules());
  std::size_t i = 0;
  std::int64_t lap = 0;
  for (auto _ : state) {
    Posture p = postures[i];
    p.t_ns += lap;
    benchmark::DoNotOptimize(monitor.update(p));
    if (++i == postures.size()) {
      i = 0;
      lap += 60'000'000'000;
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_AlertMonitorBuiltInRules);

}  // namespace
}  // namespace spinewatch

BENCHMARK_MAIN();
