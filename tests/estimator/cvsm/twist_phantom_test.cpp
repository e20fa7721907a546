// Axial twist on the phantom through the whole estimator (issue 19's
// finding): a true 20° twist of T1 against L5 is either published as a
// twist or flagged, never a confident untwisted `tracking` line; and
// scenarios without twist are rarely flagged. Developed on the generic
// subject; asserted on the petite and tall ones (docs/cvsm.md, "Axial twist").
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

#include "spinewatch/estimator/fit_flags.hpp"
#include "test_support.hpp"
#include "twist_phantom_run.hpp"

namespace spinewatch {
namespace {

// The bound on false twist_unresolved flags, percent of tracked pairs
// (measured: see docs/cvsm.md, "Axial twist").
constexpr int kFalseFlagPercent = 5;

bool trace_wanted() { return std::getenv("SPINEWATCH_TWIST_TRACE") != nullptr; }

void print(const std::string& what, const std::vector<test::TwistFrame>& frames) {
  if (!trace_wanted()) return;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto& f = frames[i];
    std::printf("%s %3zu truth %6.1f fit %6.1f published %6.1f margin %5lld %s %s\n", what.c_str(), i, f.truth,
                f.fit.value_or(NAN), f.published.value_or(NAN), static_cast<long long>(f.sign_margin_px.value_or(-1)),
                std::string(to_string(f.state)).c_str(), f.flag.c_str());
  }
}

TEST(TwistPhantom, Trace) {
  if (!trace_wanted()) GTEST_SKIP() << "SPINEWATCH_TWIST_TRACE unset";
  const char* scenario = std::getenv("SPINEWATCH_TWIST_SCENARIO");
  const char* subject = std::getenv("SPINEWATCH_TWIST_SUBJECT");
  auto frames = test::run_twist_phantom(scenario ? scenario : "twist", subject ? subject : "generic", 3);
  ASSERT_TRUE(frames) << frames.error().message;
  print(std::string(scenario ? scenario : "twist") + "/" + (subject ? subject : "generic"), *frames);
}

// Near the peaks of the `twist` scenario (|true twist| ≥ 15°, the script
// going to ±20°): a tracked pair either publishes a twist beyond 10° or is
// flagged twist_unresolved; never a confident untwisted line. On subjects
// other than the generic one the fit was developed on.
TEST(TwistPhantom, ATwentyDegreeTwistIsSeenOrFlaggedNeverConfidentlyUntwisted) {
  for (const char* subject : {"petite", "tall"}) {
    auto frames = test::run_twist_phantom("twist", subject, 3);
    ASSERT_TRUE(frames) << frames.error().message;
    print(std::string("twist/") + subject, *frames);
    int peak = 0, confident_untwisted = 0, seen = 0, flagged = 0, tracked = 0;
    double abs_error = 0;
    for (const auto& f : *frames) {
      if (std::abs(f.truth) < 15 || !f.tracking()) continue;
      ++peak;
      ASSERT_TRUE(f.published);
      if (f.flag == kTwistUnresolvedFlag) ++flagged;
      if (f.unflagged_tracking()) ++tracked;
      if (f.unflagged_tracking() && std::abs(*f.published) < 10) ++confident_untwisted;
      // Resolved: the magnitude within 5° and the sign right.
      if (f.unflagged_tracking()) {
        EXPECT_NEAR(*f.published, f.truth, 5.0) << subject;
      }
      if (std::abs(*f.published) >= 10) ++seen;
      abs_error += std::abs(std::abs(*f.published) - std::abs(f.truth));
    }
    std::printf("twist/%s: %d tracked pairs at |true twist| >= 15 deg: %d published >= 10 deg, %d flagged, "
                "%d unflagged, mean |magnitude error| %.1f deg\n",
                subject, peak, seen, flagged, tracked, peak ? abs_error / peak : 0.0);
    EXPECT_GE(peak, 20) << subject;
    EXPECT_EQ(confident_untwisted, 0) << subject;
  }
}

// Scenarios without a twist beyond 6°: the flag stays rare. Under the
// sanitizers every other subject/scenario run (test::sanitizer_sample).
TEST(TwistPhantom, FalseFlagsAreRareWithoutATwist) {
  std::vector<std::pair<const char*, const char*>> runs;
  for (const char* subject : {"petite", "tall"})
    for (const char* scenario : {"upright", "flexion", "lateral_left", "seated_flexion", "sway"})
      runs.emplace_back(subject, scenario);
  runs = test::sanitizer_sample(runs, 2);
  int pairs = 0, flags = 0, false_twists = 0;
  for (const auto& [subject, scenario] : runs) {
    auto frames = test::run_twist_phantom(scenario, subject, 3);
    ASSERT_TRUE(frames) << frames.error().message;
    print(std::string(scenario) + "/" + subject, *frames);
    int here = 0, here_flags = 0;
    for (const auto& f : *frames) {
      if (!f.tracking()) continue;
      ++here;
      if (f.flag == kTwistUnresolvedFlag) ++here_flags;
      // A twist published beyond the 10° limit where the truth is within 6°.
      if (f.unflagged_tracking() && f.published && std::abs(*f.published) > 10 && std::abs(f.truth) < 6) ++false_twists;
    }
    std::printf("%s/%s: %d of %d tracked pairs flagged twist_unresolved\n", scenario, subject, here_flags, here);
    pairs += here;
    flags += here_flags;
  }
  std::printf("without twist: %d of %d tracked pairs flagged (%.1f %%), %d published beyond 10 deg\n", flags, pairs,
              pairs ? 100.0 * flags / pairs : 0.0, false_twists);
  EXPECT_GT(pairs, 80 * static_cast<int>(runs.size()));  // 88 tracked pairs a run or more (measured)
  EXPECT_LE(flags * 100, pairs * kFalseFlagPercent);
  EXPECT_EQ(false_twists, 0);
}

}  // namespace
}  // namespace spinewatch
