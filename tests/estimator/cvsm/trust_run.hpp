#pragma once
// The trust tests' run (issue 31: no posture published as tracking far
// from the truth): a phantom render with its station geometry, desk or
// heading, fitted pair by pair from its silhouettes alone, and what was
// tracked, lost and confidently wrong.
#include <algorithm>
#include <cstdio>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "phantom_run.hpp"

namespace spinewatch::test {

// A tracking posture with a vertebra farther than this from the truth is
// confidently wrong (issue 31).
inline constexpr double kWrongMm = 50;

// What the trust tests count over the person frames of one render.
struct TrustRun {
  int person_frames = 0, tracking = 0, lost = 0;
  int wrong = 0;        // tracking postures with a vertebra > kWrongMm off
  double worst_mm = 0;  // of any vertebra of any tracking posture
  double neck_sum_mm = 0, waist_sum_mm = 0;  // over the tracking postures
  double neck_mean() const { return tracking > 0 ? neck_sum_mm / tracking : 0.0; }
  double waist_mean() const { return tracking > 0 ? waist_sum_mm / tracking : 0.0; }
};
using TrackedFrame = std::function<void(const phantom::PhantomFrame& frame, const CvsmResult& result)>;
// Changes a rendered frame before it is fitted (index: the frame's).
using FrameEdit = std::function<void(int index, phantom::PhantomFrame& frame)>;

// The render of `po` (its station geometry, heading, desk …) fitted pair by
// pair from its silhouettes alone; `each` also sees every tracking pair,
// `each_fitted` every person pair the fit estimated (tracking, init, and
// lost pairs the fit went on from, e.g. lower_body_hidden).
// `what` names the run in the line it prints.
// `edit`, where given, changes each frame before it is fitted.
inline TrustRun track_for_trust(const phantom::PhantomOptions& po, const CvsmOptions& options, const std::string& what,
                                const TrackedFrame& each = {}, const TrackedFrame& each_fitted = {},
                                const FrameEdit& edit = {}) {
  TrustRun run;
  auto seq = phantom::PhantomSequence::create(po);
  EXPECT_TRUE(seq.ok()) << seq.error().message;
  if (!seq.ok()) return run;
  auto view_of = [](const cv::Mat& m) { return LumaView{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; };
  SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
  CvsmTracker tracker(seq->options().rig, options);
  for (int i = 0; i < seq->frame_count(); ++i) {
    phantom::PhantomFrame f = seq->render(i);
    if (edit) edit(i, f);
    const CvsmResult r = tracker.track(frontal.extract(view_of(f.luma[0])), lateral.extract(view_of(f.luma[1])));
    if (!f.truth.vertebrae) continue;  // an empty frame
    ++run.person_frames;
    if (each_fitted && r.estimated) each_fitted(f, r);
    if (r.state == TrackingState::Lost) ++run.lost;
    if (r.state != TrackingState::Tracking) continue;
    ++run.tracking;
    double worst = 0;
    for (std::size_t k = 0; k < kVertebraCount; ++k)
      worst = std::max(worst, (r.vertebrae[k].body_center - (*f.truth.vertebrae)[k].body_center).norm());
    run.worst_mm = std::max(run.worst_mm, worst);
    run.wrong += worst > kWrongMm;
    run.neck_sum_mm += (r.neck - *f.truth.neck).norm();
    run.waist_sum_mm += (r.waist - *f.truth.waist).norm();
    if (each) each(f, r);
  }
  std::printf("%s: tracking %d / lost %d of %d person frames; neck %.1f mm, waist %.1f mm; worst vertebra %.0f mm "
              "(%d > %.0f)\n",
              what.c_str(), run.tracking, run.lost, run.person_frames, run.neck_mean(), run.waist_mean(), run.worst_mm,
              run.wrong, kWrongMm);
  return run;
}

inline phantom::Subject load_named_subject(const std::string& file_stem) {
  auto subject = phantom::load_subject(test::source_dir() + "/config/subjects/" + file_stem + ".json");
  EXPECT_TRUE(subject.ok()) << subject.error().message;
  return subject.ok() ? *subject : phantom::Subject{};
}

}  // namespace spinewatch::test
