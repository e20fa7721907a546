// A station started with the subject in view of a cluttered room: the
// bootstrap cannot predict the scene behind them, so there is no
// background. The estimator must say so, with why and what to do, once —
// never a silent `init` for ever — and must not publish a posture.
#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <memory>
#include <string>

#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/phantom/phantom.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

int count_containing(const std::vector<std::string>& lines, const std::string& text) {
  return static_cast<int>(
      std::count_if(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(text) != std::string::npos; }));
}

TEST(BackgroundStall, ACrowdedRoomWithTheSubjectInViewIsNamedOnceWithTheFix) {
  phantom::PhantomOptions po;
  po.scenario = "reach";
  po.room = phantom::RoomKind::Cluttered;
  po.empty_frames = 0;  // the person is in view from the first frame
  po.frames = 200;
  auto seq = phantom::PhantomSequence::create(po);
  ASSERT_TRUE(seq.ok()) << seq.error().message;

  auto ring = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(64);
  spdlog::default_logger()->sinks().push_back(ring);
  PostureEstimator estimator(seq->options().rig, EstimatorOptions{});
  int init = 0, published = 0;
  for (int i = 0; i < seq->frame_count(); ++i) {
    const Posture p = estimator.process(phantom::camera_pair(seq->render(i)));
    init += p.state == TrackingState::Init;
    published += p.state == TrackingState::Tracking;
  }
  spdlog::default_logger()->sinks().pop_back();
  const std::vector<std::string> log = ring->last_formatted();

  EXPECT_EQ(published, 0) << "a posture on a background that was never seen";
  EXPECT_EQ(init, seq->frame_count());
  EXPECT_EQ(count_containing(log, "still no frontal background"), 1) << "said once, not per pair";
  EXPECT_EQ(count_containing(log, "spinewatch background"), 2) << "the start and the stall both name the fix";
  EXPECT_EQ(count_containing(log, "too cluttered"), 1) << "the reason: the room, not the subject";
}

}  // namespace
}  // namespace spinewatch
