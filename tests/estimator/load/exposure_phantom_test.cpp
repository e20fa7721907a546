// Exposure over a two-minute phantom shift (issue 19's "done when"): the
// estimator's summaries against the zone times of the script's true
// spine, computed here from the ground truth's T1 and L5 alone.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "spinewatch/estimator/load/exposure_accumulator.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch {
namespace {

constexpr double kFrame_s = 1.0 / 30.0;

// Sagittal tilt of the L5→T1 line from vertical, degrees (+ forward):
// the trunk inclination of docs/exposure.md, written out again.
double sagittal_tilt_deg(const SpinePose& spine) {
  const Eigen::Vector3d d = spine[kNeckIndex].body_center - spine[kWaistIndex].body_center;
  return std::atan2(d.x(), d.y()) * 180.0 / M_PI;
}

// Tilt of the same line towards the subject's right, degrees.
double frontal_tilt_deg(const SpinePose& spine) {
  const Eigen::Vector3d d = (spine[kNeckIndex].body_center - spine[kWaistIndex].body_center).normalized();
  return std::asin(d.z()) * 180.0 / M_PI;
}

// Axial rotation of T1 relative to L5 (the twist about the vertical of a
// swing-twist split), degrees.
double axial_twist_deg(const SpinePose& spine) {
  const Eigen::Quaterniond rel = spine[kWaistIndex].q.conjugate() * spine[kNeckIndex].q;
  return 2.0 * std::atan2(rel.y(), rel.w()) * 180.0 / M_PI;
}

// Entries beyond 10° and the time beyond, over the tracked frames.
struct Beyond {
  bool over = false;
  int entries = 0;
  double over_s = 0;
  void add(double deg) {
    const bool now = std::abs(deg) > 10.0;
    if (now && !over) ++entries;
    if (now) over_s += kFrame_s;
    over = now;
  }
};

// ISO 11226 zones with the station's 2° extension margin, by hand.
int zone_of(double inclination_deg) {
  if (inclination_deg < -2.0) return 0;
  if (inclination_deg <= 20.0) return 1;
  if (inclination_deg <= 60.0) return 2;
  return 3;
}

TEST(ExposurePhantom, ZoneTimesOfATwoMinuteShiftMatchTheTrueSpineWithinOneFrame) {
  phantom::PhantomOptions po;
  po.scenario = "shift";
  po.frames = 3600;  // two minutes at 30 fps
  po.seed = 3;
  auto sequence = phantom::PhantomSequence::create(po);
  ASSERT_TRUE(sequence) << sequence.error().message;
  EstimatorOptions eo;
  eo.subject.spine_placement = SpinePlacementMode::Generic;  // the phantom's generic subject
  PostureEstimator estimator(po.rig, eo);
  ExposureAccumulator accumulator;  // 60 s intervals

  std::vector<ExposureSummary> summaries;
  std::optional<double> neutral_tilt, neutral_lateral, neutral_twist;
  Beyond true_lateral, true_twist;
  // Expected tracked time per zone, per interval (0: [0, 60 s), 1: [60, 120 s), 2: the rest) and for the shift.
  std::array<std::array<double, 4>, 3> expected{};
  std::array<double, 4> expected_shift{};
  int tracked = 0, person = 0, worst_zone_disagreements = 0;
  for (int i = 0; i < sequence->frame_count(); ++i) {
    const phantom::PhantomFrame frame = sequence->render(i);
    Posture posture = estimator.process(phantom::grey_pair(frame));
    posture.seq = frame.seq;
    posture.t_ns = frame.t_ns;
    for (auto& s : accumulator.add(posture)) summaries.push_back(s);
    if (!frame.truth.vertebrae) continue;
    ++person;
    const double tilt = sagittal_tilt_deg(*frame.truth.vertebrae);
    if (!neutral_tilt) {  // the script starts upright
      neutral_tilt = tilt;
      neutral_lateral = frontal_tilt_deg(*frame.truth.vertebrae);
      neutral_twist = axial_twist_deg(*frame.truth.vertebrae);
    }
    if (posture.state != TrackingState::Tracking || !posture.ergonomics) continue;
    ++tracked;
    const int z = zone_of(tilt - *neutral_tilt);
    const auto window = std::min<std::size_t>(2, std::size_t(frame.t_ns / 60'000'000'000));
    expected[window][std::size_t(z)] += kFrame_s;
    expected_shift[std::size_t(z)] += kFrame_s;
    true_lateral.add(frontal_tilt_deg(*frame.truth.vertebrae) - *neutral_lateral);
    true_twist.add(axial_twist_deg(*frame.truth.vertebrae) - *neutral_twist);
    if (zone_of(posture.ergonomics->trunk_inclination_deg) != z) ++worst_zone_disagreements;
  }
  for (auto& s : accumulator.finish()) summaries.push_back(s);

  // Every zone of ISO 11226 is visited, and nearly every person frame tracked.
  for (double t : expected_shift) EXPECT_GT(t, 3.0);
  EXPECT_GE(tracked, person * 97 / 100) << tracked << " of " << person;

  ASSERT_EQ(summaries.size(), 6u);  // [0, 60), [60, 120), the partial rest; each with the shift so far
  const ExposureSummary& shift = summaries.back();
  ASSERT_EQ(shift.scope, SummaryScope::Shift);
  EXPECT_NEAR(shift.tracked_s, tracked * kFrame_s, 1e-3);
  for (std::size_t z = 0; z < 4; ++z)
    EXPECT_NEAR(shift.zone_s[z], expected_shift[z], kFrame_s + 1e-6)
        << zone_key(InclinationZone(z)) << ": " << worst_zone_disagreements << " frames disagree in all";
  for (std::size_t w = 0; w < 3; ++w) {
    const ExposureSummary& interval = summaries[2 * w];
    ASSERT_EQ(interval.scope, SummaryScope::Interval);
    for (std::size_t z = 0; z < 4; ++z)
      EXPECT_NEAR(interval.zone_s[z], expected[w][z], kFrame_s + 1e-6) << "interval " << w << " " << zone_key(InclinationZone(z));
  }
  // Side bends: the script's three 30° bends tilt the L5→T1 line about
  // 15°, beyond 10° three times (the last hold's 15° bend tilts it 7°).
  EXPECT_EQ(true_lateral.entries, 3);
  EXPECT_EQ(shift.lateral_bend.entries, 3u);
  EXPECT_NEAR(shift.lateral_bend.over_s, true_lateral.over_s, 2 * kFrame_s);
  // Twists: the truth turns T1 against L5 beyond 10° four times (±20°
  // three times, 15° in the last hold). The accurate model takes the
  // CVSM's twist (without it: under 2° published for a true 20°, 0
  // entries); every entry is seen, and on this rig the sign is
  // always resolved (docs/exposure.md, "Known limits"). The fit's twist
  // moves in 2° steps and runs under the peaks: the last hold's 15° is
  // fitted at 9.05° or 11.04° from pair to pair, across the limit; the
  // entry's hysteresis (bend_twist_hysteresis_deg, 2°) keeps those steps
  // one entry, but one pair fitted at 4.1° ends it (measured: 5 entries
  // for 4; 8 without the hysteresis; 7.23 s beyond against 7.87 s true).
  EXPECT_EQ(true_twist.entries, 4);
  EXPECT_GE(shift.axial_twist.entries, 4u);
  EXPECT_LE(shift.axial_twist.entries, 5u);
  EXPECT_NEAR(shift.axial_twist.over_s, true_twist.over_s, 24 * kFrame_s);
  EXPECT_EQ(shift.twist_unresolved_s, 0.0);
  RecordProperty("twist_entries_true", true_twist.entries);
  RecordProperty("twist_entries_estimated", int(shift.axial_twist.entries));
  std::printf("zones (s): estimated / true: ");
  for (std::size_t z = 0; z < 4; ++z) std::printf("%s %.3f / %.3f  ", std::string(zone_key(InclinationZone(z))).c_str(), shift.zone_s[z], expected_shift[z]);
  std::printf("\nside bend over: %.3f / %.3f s; twist entries %u / %d, over %.3f / %.3f s, unresolved %.3f s; %d of %d "
              "person frames tracked; %d frames in another zone\n",
              shift.lateral_bend.over_s, true_lateral.over_s, shift.axial_twist.entries, true_twist.entries,
              shift.axial_twist.over_s, true_twist.over_s, shift.twist_unresolved_s, tracked, person,
              worst_zone_disagreements);
  // Coverage adds up to the recording.
  EXPECT_NEAR(shift.tracked_s + shift.init_s + shift.lost_s + shift.empty_s + shift.gap_s, shift.duration_s(), 1e-6);
  RecordProperty("zone_disagreements", worst_zone_disagreements);
}

}  // namespace
}  // namespace spinewatch
