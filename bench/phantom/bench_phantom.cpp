// The phantom's cost per frame (docs/performance.md, "The phantom"): one
// person frame rendered in both views, noise included, for each scenario
// and for the scene options that cost something per frame.
#include <benchmark/benchmark.h>

#include <string>

#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch::phantom {
namespace {

void render_frames(benchmark::State& state, PhantomOptions options) {
  options.frames = 60;
  options.empty_frames = 0;
  auto sequence = PhantomSequence::create(options);
  if (!sequence) {
    state.SkipWithError(sequence.error().message.c_str());
    return;
  }
  int index = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(sequence->render(index));
    index = (index + 1) % 60;
  }
}

void BM_RenderFrame(benchmark::State& state, const char* scenario) {
  PhantomOptions options;
  options.scenario = scenario;
  render_frames(state, options);
}
BENCHMARK_CAPTURE(BM_RenderFrame, flexion, "flexion");
BENCHMARK_CAPTURE(BM_RenderFrame, seated_flexion, "seated_flexion");
BENCHMARK_CAPTURE(BM_RenderFrame, reach, "reach");
BENCHMARK_CAPTURE(BM_RenderFrame, arms_overhead, "arms_overhead");
BENCHMARK_CAPTURE(BM_RenderFrame, carry, "carry");
BENCHMARK_CAPTURE(BM_RenderFrame, stride, "stride");
BENCHMARK_CAPTURE(BM_RenderFrame, lunge, "lunge");
BENCHMARK_CAPTURE(BM_RenderFrame, typing, "typing");

void BM_RenderFrameClutteredRoom(benchmark::State& state) {
  PhantomOptions options;
  options.scenario = "flexion";
  options.room = RoomKind::Cluttered;
  render_frames(state, options);
}
BENCHMARK(BM_RenderFrameClutteredRoom);

}  // namespace
}  // namespace spinewatch::phantom

BENCHMARK_MAIN();
