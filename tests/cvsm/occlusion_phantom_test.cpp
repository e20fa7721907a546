// A seated person behind a desk the stored background holds: the frontal
// silhouette ends at the desk's edge (docs/cvsm.md, "Occluded lower
// body"). Short renders of one subject through the CVSM; the truth is the
// phantom's.
#include <algorithm>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "phantom_run.hpp"

namespace spinewatch {
namespace {

struct DeskRun {
  int person_frames = 0, tracked = 0, wrong = 0;  // wrong: tracked, a vertebra > kWrongMm off
  double worst_mm = 0, waist_sum_mm = 0;
  double waist_mean() const { return tracked ? waist_sum_mm / tracked : 0; }
};
constexpr double kWrongMm = 50;  // the "confidently wrong"

DeskRun run_at_desk(const std::string& scenario, const std::string& subject_name, int frames) {
  DeskRun run;
  auto subject = phantom::load_subject(test::source_dir() + "/config/subjects/" + subject_name + ".json");
  EXPECT_TRUE(subject.ok());
  if (!subject.ok()) return run;
  phantom::PhantomOptions po;
  po.scenario = scenario;
  po.subject = *subject;
  po.frames = frames;
  po.seed = 3;
  po.desk = true;
  auto seq = phantom::PhantomSequence::create(po);
  EXPECT_TRUE(seq.ok());
  if (!seq.ok()) return run;
  auto view_of = [](const cv::Mat& m) { return LumaView{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; };
  SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
  CvsmTracker tracker(po.rig, test::generic_subject_options());
  for (int i = 0; i < seq->frame_count(); ++i) {
    const phantom::PhantomFrame f = seq->render(i);
    const CvsmResult r = tracker.track(frontal.extract(view_of(f.luma[0])), lateral.extract(view_of(f.luma[1])));
    if (!f.truth.vertebrae) continue;
    ++run.person_frames;
    if (r.state != TrackingState::Tracking) continue;
    ++run.tracked;
    double worst = 0;
    for (std::size_t k = 0; k < kVertebraCount; ++k)
      worst = std::max(worst, (r.vertebrae[k].body_center - (*f.truth.vertebrae)[k].body_center).norm());
    run.worst_mm = std::max(run.worst_mm, worst);
    run.wrong += worst > kWrongMm;
    run.waist_sum_mm += (r.waist - *f.truth.waist).norm();
  }
  std::printf("%s at the desk, %s: %d of %d person frames tracked, waist %.1f mm, worst %.1f mm, %d > %.0f mm\n",
              scenario.c_str(), subject_name.c_str(), run.tracked, run.person_frames, run.waist_mean(), run.worst_mm,
              run.wrong, kWrongMm);
  return run;
}

// Without the occluder's edge the fit dragged the pelvis down to explain
// the hidden legs (the waist 180–210 mm off, docs/accuracy.md) or lost
// the person; with it the trunk's own outline decides, and a pair whose
// lower body neither view sees is lost, not published.
// (The tall subject is not asserted: it is still fitted standing behind
// the desk, docs/cvsm.md, "Occluded lower body".)
TEST(Occlusion, BehindADeskNoTrackedPostureIsConfidentlyWrong) {
  for (const char* scenario : {"seated_flexion", "typing"}) {
    const DeskRun run = run_at_desk(scenario, "petite", 30);
    EXPECT_EQ(run.wrong, 0) << scenario;
    EXPECT_LE(run.worst_mm, 45.0) << scenario;  // measured 36 and 9
  }
}

TEST(Occlusion, BehindADeskTheTrunkTracksWithTheWaistNearTheTruth) {
  const DeskRun run = run_at_desk("seated_flexion", "petite", 30);
  // Measured: all 21 pairs after the subject model's 9 init pairs tracked,
  // the waist 19.1 mm off on average (without the edge: never tracked).
  EXPECT_GE(run.tracked, 16);
  EXPECT_LE(run.waist_mean(), 25.0);
}

}  // namespace
}  // namespace spinewatch
