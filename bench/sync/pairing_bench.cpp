// Capture-to-pair cost on one core: fake-device DQBUF → Frame (buffer
// lease) → pairing → pop, per pair. The fake does not write pixels (a real
// driver's DMA costs the CPU nothing), so this is our code's overhead.
#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>

#include "spinewatch/capture/fake_v4l2_device.hpp"
#include "spinewatch/capture/v4l2_camera.hpp"
#include "spinewatch/sync/frame_pairer.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

void BM_DequeueToPair(benchmark::State& state) {
  FakeV4l2Script script;
  script.fill = false;
  auto devices = {std::make_shared<FakeV4l2Device>(script), std::make_shared<FakeV4l2Device>(script)};
  std::unique_ptr<V4l2Camera> cameras[2];
  int v = 0;
  for (const auto& d : devices) {
    V4l2CameraOptions o;
    o.path = script.path;
    o.watchdog_s = 0;
    cameras[v] = std::make_unique<V4l2Camera>(o, d);
    if (!cameras[v]->start()) {
      state.SkipWithError("camera did not start");
      return;
    }
    ++v;
  }
  sync::FramePairer pairer({.fps = 30.0});
  std::uint64_t pairs = 0;
  for (auto _ : state) {
    for (int s = 0; s < 2; ++s) {
      auto frame = cameras[s]->next(1s);
      if (!frame) {
        state.SkipWithError("no frame");
        return;
      }
      pairer.push(kViews[s], std::move(*frame));
    }
    while (auto pair = pairer.pop()) {
      benchmark::DoNotOptimize(pair->frontal.bytes().data());
      ++pairs;
    }  // the pair goes here: both buffers back to the drivers
  }
  state.counters["pairs"] = static_cast<double>(pairs);
  state.SetItemsProcessed(static_cast<std::int64_t>(pairs));
}
BENCHMARK(BM_DequeueToPair)->Unit(benchmark::kMicrosecond);

void BM_PairerOnly(benchmark::State& state) {
  sync::FramePairer pairer({.fps = 30.0});
  std::uint64_t k = 0;
  for (auto _ : state) {
    const auto t = static_cast<std::int64_t>(k) * 33'333'333;
    pairer.push(View::Frontal, Frame(FrameFormat{}, {k, t}, nullptr, {}));
    pairer.push(View::Lateral, Frame(FrameFormat{}, {k, t + 1'000'000}, nullptr, {}));
    benchmark::DoNotOptimize(pairer.pop());
    ++k;
  }
}
BENCHMARK(BM_PairerOnly)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace spinewatch
