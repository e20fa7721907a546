#pragma once
// One phantom scenario through the whole estimator, frame by frame: the
// true axial twist of T1 against L5, the CVSM fit's twist, the published
// twist (ergonomics.twist_deg), the state and the fit's flag. Shared by the
// twist test and its printout (SPINEWATCH_TWIST_TRACE=1).
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "test_support.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch::test {

// Axial rotation of T1 relative to L5 (twist about the vertical of a
// swing-twist split), degrees.
inline double true_axial_twist_deg(const SpinePose& spine) {
  const Eigen::Quaterniond rel = spine[kWaistIndex].q.conjugate() * spine[kNeckIndex].q;
  return 2.0 * std::atan2(rel.y(), rel.w()) * 180.0 / M_PI;
}

struct TwistFrame {
  double truth = 0;                 // degrees, from the first person frame
  std::optional<double> fit;        // the CVSM's twist, when it fitted
  std::optional<double> published;  // ergonomics.twist_deg
  TrackingState state = TrackingState::Lost;
  std::string flag;
  std::optional<std::int64_t> sign_margin_px;  // the mirrored twist's extra cost, when checked
  bool tracking() const { return state == TrackingState::Tracking; }
  bool unflagged_tracking() const { return tracking() && flag.empty(); }
};

inline Result<std::vector<TwistFrame>> run_twist_phantom(const std::string& scenario, const std::string& subject_name,
                                                          unsigned seed, std::optional<int> frames = std::nullopt) {
  phantom::PhantomOptions po;
  po.scenario = scenario;
  po.seed = seed;
  po.frames = frames;
  if (subject_name != "generic") {
    auto subject = phantom::load_subject(test::source_dir() + "/config/subjects/" + subject_name + ".json");
    if (!subject.ok()) return subject.error();
    po.subject = *subject;
  }
  auto sequence = phantom::PhantomSequence::create(po);
  if (!sequence.ok()) return sequence.error();
  EstimatorOptions eo;
  eo.subject.spine_placement = SpinePlacementMode::Generic;  // the phantom's subjects carry the generic spine
  PostureEstimator estimator(po.rig, eo);
  std::vector<TwistFrame> out;
  std::optional<double> neutral;
  for (int i = 0; i < sequence->frame_count(); ++i) {
    const phantom::PhantomFrame frame = sequence->render(i);
    const Posture posture = estimator.process(phantom::grey_pair(frame));
    if (!frame.truth.vertebrae) continue;
    const double truth = true_axial_twist_deg(*frame.truth.vertebrae);
    if (!neutral) neutral = truth;  // every scenario starts untwisted
    TwistFrame f;
    f.truth = truth - *neutral;
    f.state = posture.state;
    f.flag = posture.fit.flag.value_or("");
    const EstimatorTrace trace = estimator.last_trace();
    if (trace.fit && trace.fit->estimated) f.fit = trace.fit->pose.twist;
    if (trace.fit) f.sign_margin_px = trace.fit->twist_sign_margin_px;
    if (posture.ergonomics) f.published = posture.ergonomics->twist_deg;
    out.push_back(f);
  }
  return out;
}

}  // namespace spinewatch::test
