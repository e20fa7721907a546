// Alert rules against hand-made sequences (docs/exposure.md, "Alerts"),
// and on the phantom's flexion scenario through the whole estimator.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "spinewatch/estimator/load/alert_json.hpp"
#include "spinewatch/estimator/load/alerts.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/phantom/phantom.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

constexpr std::int64_t kMs = 1'000'000;

Posture tracked(std::int64_t t_ms, double inclination, double twist = 0, std::optional<double> l5 = std::nullopt) {
  Posture p;
  p.seq = std::uint64_t(t_ms / 100);
  p.t_ns = t_ms * kMs;
  p.state = TrackingState::Tracking;
  Ergonomics e;
  e.trunk_inclination_deg = inclination;
  e.twist_deg = twist;
  p.ergonomics = e;
  if (l5) p.loads = {{"L5", *l5}};
  return p;
}

std::vector<AlertEvent> run(AlertMonitor& m, const std::vector<Posture>& postures) {
  std::vector<AlertEvent> out;
  for (const auto& p : postures)
    for (auto& e : m.update(p)) out.push_back(e);
  return out;
}

AlertRule stooped() {
  AlertRule r;
  r.name = "stooped";
  r.inclination_above_deg = 60;
  r.hold_s = 0.3;
  r.hysteresis_deg = 5;
  r.min_interval_s = 2;
  return r;
}

TEST(AlertMonitor, RaisesAfterTheHoldAndClearsWithHysteresis) {
  AlertMonitor m({stooped()});
  // 100 ms apart: above 60° from 0.1 s; held 0.3 s at 0.4 s; 57° is within
  // the 5° hysteresis, 54° is not.
  const auto events = run(m, {tracked(0, 50), tracked(100, 62), tracked(200, 65), tracked(300, 61), tracked(400, 63),
                              tracked(500, 57), tracked(600, 56), tracked(700, 54), tracked(800, 50)});
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].change, AlertChange::Raised);
  EXPECT_EQ(events[0].t_ns, 400 * kMs);
  EXPECT_NEAR(events[0].held_s, 0.3, 1e-9);
  EXPECT_DOUBLE_EQ(*events[0].inclination_deg, 63);
  EXPECT_FALSE(events[0].twist_deg);  // the rule does not look at it
  EXPECT_EQ(events[1].change, AlertChange::Cleared);
  EXPECT_EQ(events[1].t_ns, 700 * kMs);
  EXPECT_NEAR(events[1].held_s, 0.3, 1e-9);
}

TEST(AlertMonitor, AShortExcursionOrALostPostureDoesNotRaise) {
  AlertMonitor m({stooped()});
  Posture lost;
  lost.t_ns = 300 * kMs;
  lost.state = TrackingState::Lost;
  EXPECT_TRUE(run(m, {tracked(0, 62), tracked(100, 62), tracked(200, 50), tracked(250, 62), lost, tracked(400, 62),
                      tracked(600, 62)})
                  .empty());
  EXPECT_EQ(run(m, {tracked(700, 62)}).size(), 1u);  // 400 → 700: held 0.3 s
}

TEST(AlertMonitor, RaisesAgainOnlyAfterTheMinimumInterval) {
  AlertMonitor m({stooped()});
  std::vector<Posture> seq;
  // Up at 0.3 s, down at 0.5 s, above again from 0.6 s: held by 0.9 s but
  // the last raise was at 0.3 s: the next may come at 2.3 s.
  for (std::int64_t t = 0; t <= 3000; t += 100) seq.push_back(tracked(t, t == 500 ? 40 : 62));
  const auto events = run(m, seq);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].t_ns, 300 * kMs);
  EXPECT_EQ(events[1].change, AlertChange::Cleared);
  EXPECT_EQ(events[1].t_ns, 500 * kMs);
  EXPECT_EQ(events[2].change, AlertChange::Raised);
  EXPECT_EQ(events[2].t_ns, 2300 * kMs);
  EXPECT_NEAR(events[2].held_s, 1.7, 1e-9);
}

TEST(AlertMonitor, EveryConditionOfARuleMustHold) {
  AlertRule r;
  r.name = "twist_while_flexed";
  r.inclination_above_deg = 20;
  r.twist_above_deg = 10;
  AlertRule c;
  c.name = "compression";
  c.compression_above_n = 3400;
  c.hysteresis_n = 200;
  AlertMonitor m({r, c});
  const auto events = run(m, {tracked(0, 30, 5, 3000.0), tracked(100, 10, -15, 3500.0), tracked(200, 30, -15, 3300.0),
                              tracked(300, 30, 0, 3100.0)});
  ASSERT_EQ(events.size(), 4u);
  EXPECT_EQ(events[0].rule, "compression");  // 3500 N at 0.1 s (hold 0)
  EXPECT_EQ(events[0].t_ns, 100 * kMs);
  EXPECT_EQ(events[1].rule, "twist_while_flexed");  // both at 0.2 s
  EXPECT_EQ(events[1].t_ns, 200 * kMs);
  EXPECT_DOUBLE_EQ(*events[1].twist_deg, -15);
  EXPECT_EQ(events[2].rule, "twist_while_flexed");  // cleared at 0.3 s
  EXPECT_EQ(events[2].change, AlertChange::Cleared);
  EXPECT_EQ(events[3].rule, "compression");  // 3300 N stays within the 200 N hysteresis; 3100 N clears
  EXPECT_EQ(events[3].change, AlertChange::Cleared);
  EXPECT_EQ(events[3].t_ns, 300 * kMs);
}

TEST(AlertRules, TheBuiltInFileParsesAndBadFilesNameTheLineAndKey) {
  const auto& builtin = builtin_alert_rules();
  ASSERT_EQ(builtin.size(), 3u);
  EXPECT_EQ(builtin[0].name, "stooped");
  EXPECT_DOUBLE_EQ(*builtin[0].inclination_above_deg, 60);
  EXPECT_DOUBLE_EQ(builtin[0].hold_s, 10);
  auto no_condition = parse_alert_rules("[[rule]]\nname = \"x\"\nhold_s = 1\n", "a.toml");
  ASSERT_FALSE(no_condition);
  EXPECT_NE(no_condition.error().message.find("a.toml:1: rule[0]: names no condition"), std::string::npos)
      << no_condition.error().message;
  auto typo = parse_alert_rules("[[rule]]\nname = \"x\"\ninclination_above = 60\n", "a.toml");
  ASSERT_FALSE(typo);
  EXPECT_EQ(typo.error().message, "a.toml:3: rule[0].inclination_above: unknown key");
  auto range = parse_alert_rules("[[rule]]\nname = \"x\"\ncompression_above_n = -5\n", "a.toml");
  ASSERT_FALSE(range);
  EXPECT_EQ(range.error().message, "a.toml:3: rule[0].compression_above_n: -5 is out of range [0, 100000]");
  auto twice = parse_alert_rules("[[rule]]\nname = \"x\"\ntwist_above_deg = 5\n[[rule]]\nname = \"x\"\ntwist_above_deg = 6\n",
                                 "a.toml");
  ASSERT_FALSE(twice);
  EXPECT_NE(twice.error().message.find("rule[1].name: \"x\" is used twice"), std::string::npos);
  EXPECT_TRUE(parse_alert_rules("", "empty.toml")->empty());
}

TEST(AlertJson, LinesValidateAgainstTheSchema) {
  AlertMonitor m({stooped()});
  test::TempDir dir;
  {
    std::ofstream f(dir / "a.ndjson");
    for (const auto& e : run(m, {tracked(0, 62), tracked(300, 64), tracked(600, 40)}))
      f << encode_alert(e, {.station = "bench 3", .worker = std::nullopt, .utc_offset_ns = 1'764'662'100'000'000'000}) << '\n';
  }
  EXPECT_EQ(test::validate_ndjson(dir / "a.ndjson"), "");
  EXPECT_NE(test::read_file(dir / "a.ndjson").find("\"event\":\"raised\""), std::string::npos);
}

// The phantom bends forward 0 → 50° → 0 in 3 s (the L5→T1 line to about
// 33°): a rule "above 25° for 0.2 s, 3° hysteresis" raises once, 0.2 s
// after the true spine passes 25°, and clears once, when it falls below
// 22° — each within two frames of the truth.
TEST(AlertPhantom, FiresAndClearsOnTheFlexionScenarioAsConfigured) {
  phantom::PhantomOptions po;
  po.scenario = "flexion";
  po.seed = 3;
  auto sequence = phantom::PhantomSequence::create(po);
  ASSERT_TRUE(sequence);
  EstimatorOptions eo;
  eo.subject.spine_placement = SpinePlacementMode::Generic;
  PostureEstimator estimator(po.rig, eo);
  AlertRule r;
  r.name = "bent";
  r.inclination_above_deg = 25;
  r.hold_s = 0.2;
  r.hysteresis_deg = 3;
  r.min_interval_s = 60;
  AlertMonitor monitor({r});
  std::vector<AlertEvent> events;
  std::optional<double> neutral;
  std::optional<std::int64_t> true_above, true_below;  // first passing 25° up, then 22° down
  for (int i = 0; i < sequence->frame_count(); ++i) {
    const phantom::PhantomFrame frame = sequence->render(i);
    Posture p = estimator.process(phantom::grey_pair(frame));
    p.seq = frame.seq;
    p.t_ns = frame.t_ns;
    for (auto& e : monitor.update(p)) events.push_back(e);
    if (!frame.truth.vertebrae) continue;
    const auto& s = *frame.truth.vertebrae;
    const Eigen::Vector3d d = s[kNeckIndex].body_center - s[kWaistIndex].body_center;
    const double tilt = std::atan2(d.x(), d.y()) * 180 / M_PI;
    if (!neutral) neutral = tilt;
    if (!true_above && tilt - *neutral > 25) true_above = frame.t_ns;
    if (true_above && !true_below && tilt - *neutral < 22) true_below = frame.t_ns;
  }
  ASSERT_TRUE(true_above && true_below);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].change, AlertChange::Raised);
  EXPECT_EQ(events[1].change, AlertChange::Cleared);
  const double frame_s = 1.0 / 30;
  EXPECT_NEAR(events[0].t_ns * 1e-9, *true_above * 1e-9 + 0.2, 2 * frame_s + 1e-6);
  EXPECT_NEAR(events[1].t_ns * 1e-9, *true_below * 1e-9, 2 * frame_s + 1e-6);
  std::printf("raised at %.3f s (truth + 0.2 s: %.3f), cleared at %.3f s (truth: %.3f)\n", events[0].t_ns * 1e-9,
              *true_above * 1e-9 + 0.2, events[1].t_ns * 1e-9, *true_below * 1e-9);
}

}  // namespace
}  // namespace spinewatch
