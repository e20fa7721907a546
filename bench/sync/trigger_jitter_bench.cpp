// Master-mode scheduling jitter: how late the trigger thread wakes behind
// its absolute deadlines (clock_nanosleep TIMER_ABSTIME, CLOCK_MONOTONIC),
// driving the fake line at 200 Hz for 2 s. SCHED_FIFO when allowed.
#include <benchmark/benchmark.h>

#include <chrono>
#include <thread>

#include "spinewatch/sync/fake_trigger_line.hpp"
#include "spinewatch/sync/trigger_master.hpp"

namespace spinewatch::sync {
namespace {

void BM_TriggerMasterWakeLatency(benchmark::State& state) {
  const int priority = static_cast<int>(state.range(0));
  LatencySummary s;
  bool realtime = false;
  for (auto _ : state) {
    FakeTriggerLine line;
    TriggerMaster master(line, {.fps = 200.0, .pulse_us = 1000, .realtime_priority = priority}, nullptr);
    std::this_thread::sleep_for(std::chrono::seconds(2));
    master.stop();
    s = master.wake_latency();
    realtime = master.realtime();
  }
  state.counters["edges"] = static_cast<double>(s.count);
  state.counters["mean_us"] = s.mean_us;
  state.counters["p50_us"] = s.p50_us;
  state.counters["p99_us"] = s.p99_us;
  state.counters["max_us"] = s.max_us;
  state.counters["sched_fifo"] = realtime ? 1 : 0;
}
BENCHMARK(BM_TriggerMasterWakeLatency)->Arg(0)->Arg(50)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace spinewatch::sync

BENCHMARK_MAIN();
