// The CVSM on phantom recordings: subjects unlike the generic model
// (config/subjects/petite.json, tall.json) rendered in memory, silhouettes
// learnt from the empty frames, the fit frame by frame, and the neck (T1
// body centre) and waist (L5 body centre) against the ground truth.
//
// The issue's targets (docs/cvsm.md): mean 3D error ≤ 10 mm and p95 ≤ 20 mm
// for both, no lost frame on the slow scenarios, and after `fast` (a 40°
// bend in half a second) tracking back within 5 frames. All of them are
// asserted, on all 18 scenario × subject runs.
#include <algorithm>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "test_support.hpp"
#include "trust_run.hpp"

namespace spinewatch {
namespace {

using test::max_of;
using test::mean;
using test::percentile;
using Stats = test::PhantomRunStats;

Stats run(const std::string& scenario, const std::string& subject_name) {
  auto result = test::run_phantom(scenario, subject_name, 3);
  EXPECT_TRUE(result.ok()) << result.error().message;
  if (!result.ok()) return {};
  const Stats& st = *result;
  // Columns: neck mean, p95, max, mean signed x/y/z; waist the same; lost.
  std::printf("| %-14s | %-6s | %5.1f | %5.1f | %5.1f | %+6.1f %+6.1f %+6.1f | %5.1f | %5.1f | %5.1f | %+6.1f %+6.1f %+6.1f | %2d / %d |\n",
              scenario.c_str(), subject_name.c_str(), mean(st.neck), percentile(st.neck, 0.95), max_of(st.neck),
              st.neck_bias.x(), st.neck_bias.y(), st.neck_bias.z(), mean(st.waist), percentile(st.waist, 0.95),
              max_of(st.waist), st.waist_bias.x(), st.waist_bias.y(), st.waist_bias.z(), st.lost, st.person_frames);
  return st;
}

struct Bounds {
  double mean_mm, p95_mm;
};
constexpr Bounds kIssueTarget{10.0, 20.0};

void expect_accurate(const Stats& st, const std::string& what, Bounds b) {
  ASSERT_GT(st.person_frames, 0) << what;
  EXPECT_EQ(st.lost, 0) << what;
  EXPECT_EQ(st.neck.size(), static_cast<std::size_t>(st.person_frames)) << what;
  EXPECT_LE(mean(st.neck), b.mean_mm) << what << ": neck mean";
  EXPECT_LE(percentile(st.neck, 0.95), b.p95_mm) << what << ": neck p95";
  EXPECT_LE(mean(st.waist), b.mean_mm) << what << ": waist mean";
  EXPECT_LE(percentile(st.waist, 0.95), b.p95_mm) << what << ": waist p95";
}

class PhantomAccuracy : public ::testing::TestWithParam<const char*> {};

TEST_P(PhantomAccuracy, NeverLostAndWithinTheIssueTargetsForPetiteAndTall) {
  for (const char* subject : {"petite", "tall"}) {
    const Stats st = run(GetParam(), subject);
    expect_accurate(st, std::string(GetParam()) + "/" + subject, kIssueTarget);
  }
}

std::vector<const char*> slow_scenarios() {
  return {"upright", "flexion", "lateral_left", "lateral_right", "twist", "combined", "seated_flexion", "sway"};
}

INSTANTIATE_TEST_SUITE_P(Scenarios, PhantomAccuracy, ::testing::ValuesIn(slow_scenarios()),
                         [](const auto& info) { return std::string(info.param); });

TEST(PhantomAccuracyFast, RecoversWithinFiveFramesAfterAFastBend) {
  for (const char* subject : {"petite", "tall"}) {
    const Stats st = run("fast", subject);
    ASSERT_GT(st.person_frames, 0);
    EXPECT_LE(st.longest_lost_run, 5) << subject;
    EXPECT_TRUE(st.tracking_at_end) << subject;
    // The frames that were tracked are as good as on the slow scenarios.
    EXPECT_LE(mean(st.neck), kIssueTarget.mean_mm) << subject;
    EXPECT_LE(mean(st.waist), kIssueTarget.mean_mm) << subject;
  }
}

// The provisional subject model (docs/cvsm.md, "Provisional model"): a
// measured adult (ANSUR II 28496, the development subject) bending
// forward, fitted from its silhouettes by a tracker with the defaults
// (tracking from the 3rd of the model's 10 pairs) and by one that
// publishes nothing before the model is complete. (The default phantom
// subject, 15936, is no case for it: his facing side stays undecided over
// the whole building, so no early posture is published.)
// The first is tracking from the 3rd pair with the person, every
// provisional posture within the bound of a trusted one, and from the
// 10th pair on both trackers publish the same postures.
TEST(ProvisionalModel, TracksFromTheThirdPairAndLeavesTheCompleteModelsPosturesAsTheyWere) {
  phantom::PhantomOptions po;
  po.scenario = "flexion";
  auto subject = phantom::load_ansur_subject("ansur:28496", test::source_path(std::string(anthropometry::kAnsurRelativeDir)));
  ASSERT_TRUE(subject.ok()) << subject.error().message;
  po.subject = *subject;
  po.frames = 16;
  auto seq = phantom::PhantomSequence::create(po);
  ASSERT_TRUE(seq.ok()) << seq.error().message;
  auto view_of = [](const cv::Mat& m) { return LumaView{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; };
  CvsmOptions provisional;
  provisional.provisional_frames = 3;
  CvsmOptions complete_only;
  complete_only.provisional_frames = complete_only.subject_frames;
  CvsmTracker early(seq->options().rig, provisional), late(seq->options().rig, complete_only);
  SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
  int person = 0, first_tracking = -1;
  double worst_provisional_mm = 0;
  for (int i = 0; i < seq->frame_count(); ++i) {
    const phantom::PhantomFrame f = seq->render(i);
    const SilhouetteResult sf = frontal.extract(view_of(f.luma[0])), sl = lateral.extract(view_of(f.luma[1]));
    const CvsmResult a = early.track(sf, sl), b = late.track(sf, sl);
    if (!f.truth.vertebrae) continue;
    if (a.state == TrackingState::Tracking && first_tracking < 0) first_tracking = person;
    if (person < provisional.subject_frames - 1) {
      EXPECT_EQ(a.provisional, a.state == TrackingState::Tracking) << "pair " << person;
      EXPECT_NE(b.state, TrackingState::Tracking) << "pair " << person;
      if (a.state == TrackingState::Tracking)
        for (std::size_t k = 0; k < kVertebraCount; ++k)
          worst_provisional_mm = std::max(worst_provisional_mm, (a.vertebrae[k].body_center - (*f.truth.vertebrae)[k].body_center).norm());
    } else {
      EXPECT_FALSE(a.provisional) << "pair " << person;
      EXPECT_EQ(a.state, b.state) << "pair " << person;
      for (std::size_t k = 0; k < kVertebraCount; ++k)
        EXPECT_EQ(a.vertebrae[k].body_center, b.vertebrae[k].body_center) << "pair " << person << ", vertebra " << k;
    }
    ++person;
  }
  std::printf("provisional model: first tracking pair %d, worst provisional vertebra %.0f mm\n", first_tracking,
              worst_provisional_mm);
  EXPECT_EQ(first_tracking, provisional.provisional_frames - 1);
  // Measured on this render: 15 mm (pairs 3 to 9 with the person).
  EXPECT_LE(worst_provisional_mm, 30.0);
  EXPECT_LT(worst_provisional_mm, test::kWrongMm);
}

}  // namespace
}  // namespace spinewatch
