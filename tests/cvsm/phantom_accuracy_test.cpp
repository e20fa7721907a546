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
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch {
namespace {

// Person frames per scenario: 10 init frames and a smooth movement. The
// same under the sanitizers (≈ 13 s CPU there for all scenarios): a
// shorter run would be a faster movement, i.e. a different test. `fast`
// keeps its absolute timing.
int person_frames(std::string_view scenario) { return scenario == "fast" ? 60 : 66; }

LumaView view_of(const cv::Mat& m) { return {m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; }

struct Stats {
  std::vector<double> neck, waist;  // mm, valid person frames
  Eigen::Vector3d neck_bias = Eigen::Vector3d::Zero(), waist_bias = Eigen::Vector3d::Zero();  // mean signed error
  int person_frames = 0, lost = 0, longest_lost_run = 0;
  bool tracking_at_end = false;
};

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}
double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::min<double>(static_cast<double>(v.size() - 1), std::ceil(p * static_cast<double>(v.size())) - 1));
  return v[k];
}
double max_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

Stats run(const std::string& scenario, const std::string& subject_name) {
  Stats st;
  auto subject = phantom::load_subject(std::string(SPINEWATCH_SOURCE_DIR) + "/config/subjects/" + subject_name + ".json");
  EXPECT_TRUE(subject.ok()) << subject.error().message;
  if (!subject.ok()) return st;
  phantom::PhantomOptions po;
  po.scenario = scenario;
  po.subject = *subject;
  po.frames = person_frames(scenario);
  po.seed = 3;
  auto seq = phantom::PhantomSequence::create(po);
  EXPECT_TRUE(seq.ok()) << seq.error().message;
  if (!seq.ok()) return st;

  // The estimator sees only the images and the calibration.
  SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
  CvsmTracker tracker(po.rig, CvsmOptions{});
  int run_length = 0;
  for (int i = 0; i < seq->frame_count(); ++i) {
    const phantom::PhantomFrame f = seq->render(i);
    const SilhouetteResult sf = frontal.extract(view_of(f.luma[0]));
    const SilhouetteResult sl = lateral.extract(view_of(f.luma[1]));
    const CvsmResult r = tracker.track(sf, sl);
    if (!f.truth.neck) continue;  // an empty frame
    ++st.person_frames;
    if (!r.valid()) {
      ++st.lost;
      st.longest_lost_run = std::max(st.longest_lost_run, ++run_length);
      st.tracking_at_end = false;
      continue;
    }
    run_length = 0;
    st.tracking_at_end = r.state == TrackingState::Tracking;
    st.neck.push_back((r.neck - *f.truth.neck).norm());
    st.waist.push_back((r.waist - *f.truth.waist).norm());
    st.neck_bias += r.neck - *f.truth.neck;
    st.waist_bias += r.waist - *f.truth.waist;
  }
  if (!st.neck.empty()) {
    st.neck_bias /= static_cast<double>(st.neck.size());
    st.waist_bias /= static_cast<double>(st.waist.size());
  }
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

}  // namespace
}  // namespace spinewatch
