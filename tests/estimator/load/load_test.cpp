// Schultz loads (Eqs. 21–23) and the ergonomic rules.
#include <gtest/gtest.h>

#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/estimator/load/ergonomics.hpp"
#include "spinewatch/estimator/load/schultz.hpp"

namespace spinewatch {
namespace {

SchultzInputs paper_example() {
  SchultzInputs in;  // the paper's §4 figures, lever arms in cm
  in.w_head = 35;
  in.w_left_arm = in.w_right_arm = 32;
  in.w_trunk = 252;
  in.l_erector = 13.5;
  in.l_right_arm = 20;
  in.l_left_arm = -20;
  in.l_trunk = 3.4;
  in.l_head = 14.7;
  return in;
}

TEST(Schultz, PaperWorkedExample) {
  const SchultzResult r = schultz(paper_example());
  // Eq. 23 with the paper's figures: (3.4·252 + 14.7·35 − 20·32 + 20·32) / 13.5
  // + 351 = 1371.3 / 13.5 + 351 = 452.58 N. The paper prints 458 N; no
  // assignment of its figures to Eq. 23 gives 458 exactly (1.2 % apart),
  // see docs/spine-model.md.
  EXPECT_NEAR(r.compression_n, 351.0 + 1371.3 / 13.5, 1e-9);
  EXPECT_NEAR(r.compression_n, 458.0, 0.015 * 458.0);
  EXPECT_NEAR(r.erector_n, 1371.3 / 13.5, 1e-9);
  // Equilibrium (Eqs. 21–22) holds with the result.
  const SchultzInputs in = paper_example();
  EXPECT_NEAR(r.compression_n - r.erector_n, in.w_trunk + in.w_head + in.w_left_arm + in.w_right_arm, 1e-9);
}

TEST(Schultz, SixMillimetreShiftReproducesThePapersIncrease) {
  // The vertebra moves 6 mm posteriorly under the loads above it: the trunk
  // and head lever arms (l_t, l_h) each grow by 0.6 cm; the arm arms cancel
  // (±20 cm) and l_E moves with the vertebra.
  SchultzInputs shifted = paper_example();
  shifted.l_trunk += 0.6;
  shifted.l_head += 0.6;
  const double base = schultz(paper_example()).compression_n;
  const double after = schultz(shifted).compression_n;
  // ΔC = 0.6 · (252 + 35) / 13.5 = 12.76 N: the paper's 471 − 458 = 13 N, 2.8 %.
  EXPECT_NEAR(after - base, 13.0, 0.5);
  EXPECT_NEAR((after - base) / base, 0.028, 0.001);
  EXPECT_NEAR(458.0 + (after - base), 471.0, 0.5);
}

TEST(Loads, ParamsEmbeddedAndErrorsNamed) {
  const LoadParams& p = default_load_params();
  EXPECT_NEAR(p.thorax, 0.216, 1e-12);
  EXPECT_NEAR(p.erector_lever_mm, 135, 1e-12);
  auto bad = parse_load_params("[body]\nmass_kg = 75\nreference_height_mm = 1750\n[fractions]\nhead_neck = 2\n", "seg.toml");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("seg.toml:5: fractions.head_neck"), std::string::npos) << bad.error().message;
}

SpinePose tilted(double flexion_deg, double lateral_deg = 0, double twist_deg = 0) {
  SegmentalMotion m;
  m.pelvis = {flexion_deg, lateral_deg, 0};
  if (twist_deg != 0) m = [&] {
    SegmentalMotion t = distribute(generic_spine_spec(), 0, 0, twist_deg);
    t.pelvis = {flexion_deg, lateral_deg, 0};
    return t;
  }();
  return pose_spine(neutral_pose(generic_spine_spec(), 1750), m);
}

TEST(Loads, GrowDownTheSpineAndWithForwardBending) {
  const LoadParams& p = default_load_params();
  const auto upright = compute_loads(tilted(0), p);
  ASSERT_EQ(upright.size(), kVertebraCount);
  EXPECT_EQ(upright[16].level, "L5");
  // The weight above grows level by level (the erector share need not: the
  // lordosis brings lumbar vertebrae forward under the trunk).
  for (std::size_t i = 1; i < kVertebraCount; ++i) {
    const SchultzInputs a = schultz_inputs(tilted(0), i - 1, p), b = schultz_inputs(tilted(0), i, p);
    EXPECT_GT(b.w_trunk, a.w_trunk) << i;
  }
  EXPECT_GT(upright[16].compression_n, upright[0].compression_n);
  // Upright, L5 carries about the weight above it: head, arms, trunk.
  const double above = (p.head_neck + 2 * (p.upper_arm + p.forearm + p.hand) + p.thorax + p.abdomen) * p.body_mass_kg * 9.81;
  EXPECT_GE(upright[16].compression_n, above - 1e-6);
  EXPECT_LT(upright[16].compression_n, 2.5 * above);
  const auto bent = compute_loads(tilted(45), p);
  EXPECT_GT(bent[16].compression_n, 1.8 * upright[16].compression_n);
  // Σ W l / l_E by hand for L5 of the bent pose equals what compute_loads adds.
  const SchultzInputs in = schultz_inputs(tilted(45), 16, p);
  EXPECT_NEAR(bent[16].compression_n, schultz(in).compression_n, 1e-9);
  EXPECT_GT(in.l_trunk, 100.0);  // 45° forward: the trunk's centre of mass is well ahead of L5
}

std::string severity(const Ergonomics& e, const std::string& rule) {
  for (const auto& f : e.flags)
    if (f.rule == rule) return f.severity;
  return "absent";
}
double held(const Ergonomics& e, const std::string& rule) {
  for (const auto& f : e.flags)
    if (f.rule == rule) return f.held_s;
  return -1;
}

constexpr std::int64_t kSecond = 1'000'000'000;

TEST(Ergonomics, TrunkInclinationBandsAndHoldingTime) {
  const SpinePose neutral = tilted(0);
  ErgonomicsMonitor m(neutral);
  Ergonomics e = m.update(neutral, {}, 0);
  EXPECT_NEAR(e.trunk_inclination_deg, 0, 1e-9);
  EXPECT_EQ(e.reba_trunk, 1);
  EXPECT_EQ(severity(e, "iso11226_trunk_inclination"), "ok");
  EXPECT_EQ(severity(e, "niosh_compression"), "absent");  // no loads given

  e = m.update(tilted(30), {}, 1 * kSecond);
  EXPECT_NEAR(e.trunk_inclination_deg, 30, 1e-6);
  EXPECT_EQ(severity(e, "iso11226_trunk_inclination"), "conditional");
  EXPECT_NEAR(held(e, "iso11226_trunk_inclination"), 0, 1e-9);
  EXPECT_EQ(e.reba_trunk, 3);
  e = m.update(tilted(35), {}, 41 * kSecond);
  EXPECT_EQ(severity(e, "iso11226_trunk_inclination"), "conditional");
  EXPECT_NEAR(held(e, "iso11226_trunk_inclination"), 40, 1e-9);
  e = m.update(tilted(35), {}, 62 * kSecond);  // held beyond the 60 s limit
  EXPECT_EQ(severity(e, "iso11226_trunk_inclination"), "not_acceptable");
  e = m.update(tilted(10), {}, 63 * kSecond);
  EXPECT_EQ(severity(e, "iso11226_trunk_inclination"), "ok");
  EXPECT_EQ(e.reba_trunk, 2);
  e = m.update(tilted(70), {}, 64 * kSecond);
  EXPECT_EQ(severity(e, "iso11226_trunk_inclination"), "not_acceptable");
  EXPECT_EQ(e.reba_trunk, 4);
  e = m.update(tilted(-10), {}, 65 * kSecond);
  EXPECT_EQ(severity(e, "iso11226_trunk_inclination"), "not_acceptable");  // unsupported extension
  EXPECT_EQ(e.reba_trunk, 2);
}

TEST(Ergonomics, LateralBendConditionalUntilTwiceAMinute) {
  const SpinePose neutral = tilted(0);
  ErgonomicsMonitor m(neutral);
  Ergonomics e = m.update(tilted(0, 8), {}, 0);
  EXPECT_EQ(severity(e, "iso11226_lateral_bend"), "ok");
  EXPECT_EQ(e.reba_trunk, 2);  // upright but side-bent: 1 + 1
  e = m.update(tilted(0, 15), {}, 1 * kSecond);
  EXPECT_NEAR(e.lateral_bend_deg, 15, 0.01);  // the neutral L5→T1 line leans back a little
  EXPECT_EQ(severity(e, "iso11226_lateral_bend"), "conditional");
  m.update(tilted(0, 0), {}, 10 * kSecond);
  e = m.update(tilted(0, -15), {}, 20 * kSecond);  // second time within a minute
  EXPECT_EQ(severity(e, "iso11226_lateral_bend"), "not_acceptable");
  m.update(tilted(0, 0), {}, 30 * kSecond);
  e = m.update(tilted(0, 15), {}, 90 * kSecond);  // the earlier ones are over a minute old
  EXPECT_EQ(severity(e, "iso11226_lateral_bend"), "conditional");
  e = m.update(tilted(0, 0, 30), {}, 91 * kSecond);
  EXPECT_GT(std::abs(e.twist_deg), 10);
  EXPECT_EQ(severity(e, "iso11226_axial_twist"), "conditional");
}

// A side bend held near the 10° limit and estimated a step either side of
// it is one entry: it ends only 2° below the limit (bend_twist_hysteresis_deg).
// Without the hysteresis each step back over the limit is a new entry and,
// twice in a minute, not acceptable.
TEST(Ergonomics, ABendHeldAtTheLimitIsOneEntry) {
  const SpinePose neutral = tilted(0);
  auto last_severity = [&](const ErgonomicLimits& limits, std::initializer_list<double> lateral_deg) {
    ErgonomicsMonitor m(neutral, limits);
    std::int64_t t = 0;
    Ergonomics e;
    for (double d : lateral_deg) e = m.update(tilted(0, d), {}, t += kSecond);
    return severity(e, "iso11226_lateral_bend");
  };
  ErgonomicLimits limits = default_ergonomic_limits();
  EXPECT_EQ(limits.bend_twist_hysteresis_deg, 2.0);
  EXPECT_EQ(last_severity(limits, {0, 11, 9, 11, 9, 11}), "conditional");
  EXPECT_EQ(last_severity(limits, {0, 11, 7, 11}), "not_acceptable");  // back below 8°: a new entry
  limits.bend_twist_hysteresis_deg = 0;
  EXPECT_EQ(last_severity(limits, {0, 11, 9, 11}), "not_acceptable");
}

// config/segments.toml with its hysteresis set to `value`.
std::string segments_with_hysteresis(const std::string& value) {
  std::string text(segments_toml());
  const std::string key = "bend_twist_hysteresis_deg = 2.0";
  const std::size_t at = text.find(key);
  EXPECT_NE(at, std::string::npos);
  if (at != std::string::npos) text.replace(at, key.size(), "bend_twist_hysteresis_deg = " + value);
  return text;
}

TEST(Ergonomics, LimitsParsedWithTheirErrorsNamed) {
  auto parsed = parse_ergonomic_limits(segments_with_hysteresis("3.5"), "lim.toml");
  ASSERT_TRUE(parsed) << parsed.error().message;
  EXPECT_EQ(parsed->bend_twist_hysteresis_deg, 3.5);
  auto above = parse_ergonomic_limits(segments_with_hysteresis("12"), "lim.toml");
  ASSERT_FALSE(above);
  EXPECT_NE(above.error().message.find("lim.toml: limits.bend_twist_hysteresis_deg: above bend_twist_deg"),
            std::string::npos)
      << above.error().message;
  auto negative = parse_ergonomic_limits(segments_with_hysteresis("-1"), "lim.toml");
  ASSERT_FALSE(negative);
  EXPECT_NE(negative.error().message.find("bend_twist_hysteresis_deg"), std::string::npos) << negative.error().message;
}

SpinePose turned(SpinePose pose, double heading_deg) {
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(heading_deg * M_PI / 180, Eigen::Vector3d::UnitY()));
  for (auto& v : pose) {
    v.body_center = turn * v.body_center;
    v.q = turn * v.q;
  }
  return pose;
}

// The trunk's tilt is measured in the frame the subject faces: a forward
// bend is an inclination and a side bend a side bend whichever way he
// stands, with the signs of the subject (forwards, to his right).
TEST(TrunkTilt, ForwardAndSideBendsAtAnyHeading) {
  for (const double heading : {0.0, 30.0, 90.0, 180.0, 250.0, -60.0}) {
    SCOPED_TRACE(heading);
    const auto tilt = [&](const SpinePose& p) {
      const SpinePose t = turned(p, heading);
      return trunk_tilt(t, facing_of(t));
    };
    const TrunkTilt upright = tilt(tilted(0)), forward = tilt(tilted(30)), back = tilt(tilted(-10));
    const TrunkTilt right = tilt(tilted(0, 15)), left = tilt(tilted(0, -15));
    EXPECT_NEAR(upright.side_bend_deg, 0, 1e-6);
    EXPECT_NEAR(forward.inclination_deg - upright.inclination_deg, 30, 1e-6);
    EXPECT_NEAR(back.inclination_deg - upright.inclination_deg, -10, 1e-6);
    EXPECT_NEAR(forward.side_bend_deg, 0, 1e-6);
    EXPECT_NEAR(right.side_bend_deg, 15, 0.05);  // the neutral line leans back a little
    EXPECT_NEAR(left.side_bend_deg, -15, 0.05);
    EXPECT_NEAR(right.inclination_deg, upright.inclination_deg, 0.1);
  }
  // Facing is where L5's front points, laid flat: turned 90° the subject faces −Z.
  const Eigen::Vector3d facing = facing_of(turned(tilted(40), 90));
  EXPECT_NEAR(facing.x(), 0, 1e-9);
  EXPECT_NEAR(facing.y(), 0, 1e-9);
  EXPECT_NEAR(facing.z(), -1, 1e-9);
}

TEST(Ergonomics, NioshLimitsOnLumbarCompression) {
  const SpinePose neutral = tilted(0);
  ErgonomicsMonitor m(neutral);
  auto loads = [](double l4) {
    std::vector<LevelLoad> v;
    for (std::size_t i = 0; i < kVertebraCount; ++i) v.push_back({std::string(kVertebraNames[i]), i == 15 ? l4 : 500.0});
    return v;
  };
  EXPECT_EQ(severity(m.update(neutral, loads(3000), 0), "niosh_compression"), "ok");
  EXPECT_EQ(severity(m.update(neutral, loads(3500), kSecond), "niosh_compression"), "conditional");
  const Ergonomics e = m.update(neutral, loads(6500), 3 * kSecond);
  EXPECT_EQ(severity(e, "niosh_compression"), "not_acceptable");
  for (const auto& f : e.flags)
    if (f.rule == "niosh_compression") {
      EXPECT_NEAR(f.value, 6500, 1e-9);
    }
}

}  // namespace
}  // namespace spinewatch
