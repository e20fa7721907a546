// The CVSM on phantom recordings: subjects unlike the generic model
// (config/subjects/petite.json, tall.json) rendered in memory, silhouettes
// learnt from the empty frames, the fit frame by frame, and the neck (T1
// body centre) and waist (L5 body centre) against the ground truth.
//
// The issue's targets (docs/cvsm.md): mean 3D error ≤ 10 mm and p95 ≤ 20 mm
// for both, no lost frame on the slow scenarios, and after `fast` (a 40°
// bend in half a second) tracking back within 5 frames. All of them are
// asserted, on all 18 scenario × subject runs.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "phantom_run.hpp"

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

}  // namespace
}  // namespace spinewatch
