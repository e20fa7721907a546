#pragma once
// Phantom frame pairs as the cameras deliver them (YUYV, 320×240), for the
// benches that time the daemon's pipeline with something attached to it.
#include <string>
#include <vector>

#include "spinewatch/frames/frame_pair.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch::bench {

// The pipeline benches' scene: the petite subject (a generic body, so the
// estimator runs with the generic spine placement) through 90 frames of
// flexion.
inline Result<phantom::PhantomOptions> petite_flexion() {
  phantom::PhantomOptions options;
  options.scenario = "flexion";
  options.frames = 90;
  auto subject = phantom::load_subject(std::string(SPINEWATCH_SOURCE_DIR) + "/config/subjects/petite.json");
  if (!subject.ok()) return subject.error();
  options.subject = *subject;
  return options;
}

inline std::vector<FramePair> phantom_pairs(const phantom::PhantomOptions& options) {
  std::vector<FramePair> pairs;
  auto seq = phantom::PhantomSequence::create(options);
  if (!seq.ok()) return pairs;
  const auto format = FrameFormat::packed(PixelFormat::YUYV, 320, 240);
  for (int i = 0; i < seq->frame_count(); ++i) {
    const auto frame = seq->render(i);
    FramePair p;
    p.frontal = Frame::owning(format, {}, phantom::yuyv_bytes(frame, 0));
    p.lateral = Frame::owning(format, {}, phantom::yuyv_bytes(frame, 1));
    pairs.push_back(std::move(p));
  }
  return pairs;
}

}  // namespace spinewatch::bench
