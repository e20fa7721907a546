// Issue 31's phantom targets on a fixed set of scenarios and station
// geometries, for the three measured adults of the baseline table (ANSUR
// II test set: 28496, 25762, 11953; docs/accuracy.md, "Today's fit on the
// varied phantom"): at least 90 % of the person frames estimated and no
// posture published as tracking more than 50 mm off; and, on every tracking
// pair, the trunk's inclination and side bend within 5° of the truth and
// never on the wrong side (the real-footage target, here on the phantom,
// from the fit's own T1 and L5). Each is rendered in
// memory (60 person frames after the ten empty ones, seed 1, as in the
// table) and fitted with the estimator's defaults from its silhouettes
// alone, each subject on its own (under the sanitizers one subject a row,
// in turn). The rows are those where these targets
// hold today for every subject with a margin; the rows where they do not, the same
// motions twice as fast, and the third target (neck and waist within
// 10 mm on average) are in docs/accuracy.md, "Targets asserted".
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <ostream>
#include <utility>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/load/ergonomics.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "test_support.hpp"
#include "trust_run.hpp"

namespace spinewatch {
namespace {

constexpr int kPersonFrames = 60;
constexpr int kMinTracking = 54;  // 90 % of kPersonFrames (measured: 57-58, the first pairs init)

// Issue 31's real-footage target, checked here on the phantom: the trunk's
// inclination and side bend within 5° of the truth on every tracking pair,
// and never bent the other way where the truth bends 5° or more.
constexpr double kAngleTargetDeg = 5;

struct TrunkAngleCheck {
  double worst_inclination_deg = 0, worst_side_bend_deg = 0;
  int bent = 0, wrong_side = 0;

  void add(const SpinePose& truth, const SpinePose& fitted) {
    const Eigen::Vector3d facing = facing_of(truth);
    const TrunkTilt t = trunk_tilt(truth, facing), e = trunk_tilt(fitted, facing);
    worst_inclination_deg = std::max(worst_inclination_deg, std::abs(e.inclination_deg - t.inclination_deg));
    worst_side_bend_deg = std::max(worst_side_bend_deg, std::abs(e.side_bend_deg - t.side_bend_deg));
    for (auto [truth_deg, fitted_deg] : {std::pair{t.inclination_deg, e.inclination_deg}, std::pair{t.side_bend_deg, e.side_bend_deg}}) {
      if (std::abs(truth_deg) < kAngleTargetDeg) continue;
      ++bent;
      wrong_side += truth_deg * fitted_deg < 0;
    }
  }
};

struct TargetRow {
  const char* name;
  const char* scenario;
  std::optional<phantom::StationGeometry> station;
  double heading_deg = 0;
  phantom::RoomKind room = phantom::RoomKind::Plain;
};

// The default station with one of its settings changed by `set`.
template <class Set>
phantom::StationGeometry changed_station(Set set) {
  phantom::StationGeometry g;
  set(g);
  return g;
}

void PrintTo(const TargetRow& row, std::ostream* os) { *os << row.name; }

const TargetRow kRows[] = {
    {"flexion", "flexion", std::nullopt},
    {"seated_flexion", "seated_flexion", std::nullopt},
    {"tilt_20", "flexion", changed_station([](auto& g) { g.tilt_deg = 20; })},
    {"tilt_45", "flexion", changed_station([](auto& g) { g.tilt_deg = 45; })},
    {"roll_10", "flexion", changed_station([](auto& g) { g.roll_deg = 10; })},
    {"roll_25", "flexion", changed_station([](auto& g) { g.roll_deg = 25; })},
    {"pair_angle_45", "flexion", changed_station([](auto& g) { g.pair_angle_deg = 45; })},
    {"pair_angle_70", "flexion", changed_station([](auto& g) { g.pair_angle_deg = 70; })},
    {"pair_angle_135", "flexion", changed_station([](auto& g) { g.pair_angle_deg = 135; })},
    {"heading_30", "flexion", std::nullopt, 30},
    {"heading_90", "flexion", std::nullopt, 90},
    // His back to the frontal camera, followed by the front range where the
    // views decide that side (docs/cvsm.md, "Followed turned away").
    {"heading_180", "flexion", std::nullopt, 180},
    {"seated_flexion_heading_180", "seated_flexion", std::nullopt, 180},
    {"lateral_right_heading_180", "lateral_right", std::nullopt, 180},
    {"lateral_left", "lateral_left", std::nullopt},
    {"lateral_right", "lateral_right", std::nullopt},
    {"combined", "combined", std::nullopt},
    {"lateral_right_heading_90", "lateral_right", std::nullopt, 90},
    {"lateral_right_heading_300", "lateral_right", std::nullopt, 300},
    {"lateral_right_roll_25", "lateral_right", changed_station([](auto& g) { g.roll_deg = 25; })},
    {"lateral_right_pair_angle_45", "lateral_right", changed_station([](auto& g) { g.pair_angle_deg = 45; })},
    {"camera_height_1600", "flexion", changed_station([](auto& g) { g.height_mm = 1600; })},
    {"room_cluttered", "flexion", std::nullopt, 0, phantom::RoomKind::Cluttered},
};

// Every row's subjects; under the sanitizers one of them, taking turns
// row by row (test::kSanitized).
std::vector<int> subjects_of(const TargetRow& row) {
  const std::vector<int> all = {28496, 25762, 11953};
  if (!test::kSanitized) return all;
  const auto at = std::find_if(std::begin(kRows), std::end(kRows),
                               [&](const TargetRow& r) { return std::string_view(r.name) == row.name; });
  return {all[static_cast<std::size_t>(at - std::begin(kRows)) % all.size()]};
}

class PhantomTargets : public ::testing::TestWithParam<TargetRow> {};

TEST_P(PhantomTargets, NinetyPercentEstimatedAndNoConfidentlyWrongPosture) {
  const TargetRow& row = GetParam();
  for (const int id : subjects_of(row)) {
    phantom::PhantomOptions po;
    po.scenario = row.scenario;
    auto subject = phantom::load_ansur_subject("ansur:" + std::to_string(id),
                                               test::source_path(std::string(anthropometry::kAnsurRelativeDir)));
    ASSERT_TRUE(subject.ok()) << subject.error().message;
    po.subject = *subject;
    po.frames = kPersonFrames;
    po.station = row.station;
    po.heading_deg = row.heading_deg;
    po.room = row.room;
    TrunkAngleCheck angles;
    const test::TrustRun run = test::track_for_trust(
        po, CvsmOptions{}, std::string(row.name) + " " + std::to_string(id),
        [&](const phantom::PhantomFrame& f, const CvsmResult& r) { angles.add(*f.truth.vertebrae, r.vertebrae); });
    ASSERT_EQ(run.person_frames, kPersonFrames);
    EXPECT_GE(run.tracking, kMinTracking) << id;
    EXPECT_EQ(run.wrong, 0) << id << ": worst " << run.worst_mm << " mm";
    std::printf("  trunk inclination / side bend: worst %.1f / %.1f deg off, %d of %d bent frames on the wrong side\n",
                angles.worst_inclination_deg, angles.worst_side_bend_deg, angles.wrong_side, angles.bent);
    EXPECT_LE(angles.worst_inclination_deg, kAngleTargetDeg) << id;
    EXPECT_LE(angles.worst_side_bend_deg, kAngleTargetDeg) << id;
    EXPECT_EQ(angles.wrong_side, 0) << id;
  }
}


INSTANTIATE_TEST_SUITE_P(Rows, PhantomTargets, ::testing::ValuesIn(kRows),
                         [](const ::testing::TestParamInfo<TargetRow>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace spinewatch
