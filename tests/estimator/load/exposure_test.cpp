// Exposure summaries against hand-computed sequences (docs/exposure.md).
#include <gtest/gtest.h>

#include <fstream>

#include "spinewatch/estimator/fit_flags.hpp"
#include "spinewatch/estimator/load/exposure_accumulator.hpp"
#include "spinewatch/estimator/load/exposure_json.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr double kEps = 1e-9;

Posture tracked(std::int64_t t_ms, double inclination, double lateral = 0, double twist = 0,
                std::optional<double> l5_n = std::nullopt) {
  Posture p;
  p.t_ns = t_ms * kMs;
  p.state = TrackingState::Tracking;
  Ergonomics e;
  e.trunk_inclination_deg = inclination;
  e.lateral_bend_deg = lateral;
  e.twist_deg = twist;
  e.reba_trunk = reba_trunk_score({inclination, lateral, twist}, default_ergonomic_limits());
  p.ergonomics = e;
  if (l5_n) p.loads = {{"L4", *l5_n - 100}, {"L5", *l5_n}};
  return p;
}

Posture untracked(std::int64_t t_ms, TrackingState state, std::optional<std::string> flag = std::nullopt) {
  Posture p;
  p.t_ns = t_ms * kMs;
  p.state = state;
  p.fit.flag = std::move(flag);
  return p;
}

ExposureOptions every(std::int64_t interval_ms) {
  ExposureOptions o;
  o.interval_ns = interval_ms * kMs;
  return o;
}

std::vector<ExposureSummary> run(ExposureAccumulator& acc, const std::vector<Posture>& postures) {
  std::vector<ExposureSummary> out;
  for (const Posture& p : postures)
    for (auto& s : acc.add(p)) out.push_back(s);
  for (auto& s : acc.finish()) out.push_back(s);
  return out;
}

double zone(const ExposureSummary& s, InclinationZone z) { return s.zone_s[std::size_t(z)]; }

TEST(InclinationZone, BoundariesFollowIso11226WithTheExtensionMargin) {
  const ErgonomicLimits& l = default_ergonomic_limits();
  EXPECT_EQ(inclination_zone(-2.5, l), InclinationZone::Extension);
  EXPECT_EQ(inclination_zone(-2.0, l), InclinationZone::Upright);  // within the 2° margin
  EXPECT_EQ(inclination_zone(20.0, l), InclinationZone::Upright);
  EXPECT_EQ(inclination_zone(20.01, l), InclinationZone::Flexed);
  EXPECT_EQ(inclination_zone(60.0, l), InclinationZone::Flexed);
  EXPECT_EQ(inclination_zone(60.01, l), InclinationZone::Stooped);
}

TEST(RulaTrunkScore, BandsAndAdjustments) {
  const ErgonomicLimits& l = default_ergonomic_limits();
  EXPECT_EQ(rula_trunk_score({0, 0, 0}, l), 1);
  EXPECT_EQ(rula_trunk_score({15, 0, 0}, l), 2);
  EXPECT_EQ(rula_trunk_score({-15, 0, 0}, l), 2);
  EXPECT_EQ(rula_trunk_score({45, 0, 0}, l), 3);
  EXPECT_EQ(rula_trunk_score({70, 0, 0}, l), 4);
  EXPECT_EQ(rula_trunk_score({70, 12, 0}, l), 5);
  EXPECT_EQ(rula_trunk_score({70, 12, -12}, l), 6);
}

TEST(ExposureAccumulator, ZoneTimesOfOneInterval) {
  // 10 postures 100 ms apart; each stands for 100 ms (the last for the
  // last frame period), so the window is exactly [0, 1 s).
  ExposureAccumulator acc(every(1000));
  const double inclinations[] = {0, 0, 30, 30, 30, 70, 70, -10, -10, 0};
  std::vector<Posture> postures;
  for (int i = 0; i < 10; ++i) postures.push_back(tracked(i * 100, inclinations[i]));
  const auto out = run(acc, postures);
  ASSERT_EQ(out.size(), 2u);  // the interval, then the shift
  const ExposureSummary& s = out[0];
  EXPECT_EQ(s.scope, SummaryScope::Interval);
  EXPECT_EQ(out[1].scope, SummaryScope::Shift);
  EXPECT_EQ(s.start_ns, 0);
  EXPECT_EQ(s.end_ns, 1000 * kMs);
  EXPECT_FALSE(s.partial);
  EXPECT_NEAR(s.tracked_s, 1.0, kEps);
  EXPECT_NEAR(zone(s, InclinationZone::Upright), 0.3, kEps);
  EXPECT_NEAR(zone(s, InclinationZone::Flexed), 0.3, kEps);
  EXPECT_NEAR(zone(s, InclinationZone::Stooped), 0.2, kEps);
  EXPECT_NEAR(zone(s, InclinationZone::Extension), 0.2, kEps);
  EXPECT_NEAR(s.inclination_mean_deg, (30 * 3 + 70 * 2 - 10 * 2) / 10.0, 1e-9);
  EXPECT_DOUBLE_EQ(s.inclination_min_deg, -10);
  EXPECT_DOUBLE_EQ(s.inclination_max_deg, 70);
  // REBA: upright 1 (0.3 s), extension 10° → 2 (0.2 s), 30° → 3, 70° → 4.
  EXPECT_NEAR(s.reba_trunk_s[0], 0.3, kEps);
  EXPECT_NEAR(s.reba_trunk_s[1], 0.2, kEps);
  EXPECT_NEAR(s.reba_trunk_s[2], 0.3, kEps);
  EXPECT_NEAR(s.reba_trunk_s[3], 0.2, kEps);
  EXPECT_NEAR(s.reba_trunk_s[4], 0.0, kEps);
  // RULA: the same bands here (no twist, no side bend).
  EXPECT_NEAR(s.rula_trunk_s[0], 0.3, kEps);
  EXPECT_NEAR(s.rula_trunk_s[1], 0.2, kEps);
  EXPECT_NEAR(s.rula_trunk_s[2], 0.3, kEps);
  EXPECT_NEAR(s.rula_trunk_s[3], 0.2, kEps);
}

TEST(ExposureAccumulator, APostureIsSplitAtTheIntervalBoundary) {
  ExposureAccumulator acc(every(1000));
  // 0.8 s stands until 1.2 s: 0.2 s in each window.
  const auto out = run(acc, {tracked(0, 0), tracked(400, 0), tracked(800, 40), tracked(1200, 0)});
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].end_ns, 1000 * kMs);
  EXPECT_NEAR(zone(out[0], InclinationZone::Flexed), 0.2, kEps);
  EXPECT_NEAR(zone(out[0], InclinationZone::Upright), 0.8, kEps);
  EXPECT_EQ(out[2].start_ns, 1000 * kMs);
  EXPECT_EQ(out[2].end_ns, 1600 * kMs);  // the last posture stands for the last period, 0.4 s
  EXPECT_TRUE(out[2].partial);
  EXPECT_NEAR(zone(out[2], InclinationZone::Flexed), 0.2, kEps);
  EXPECT_NEAR(zone(out[2], InclinationZone::Upright), 0.4, kEps);
  // The shift covers both.
  EXPECT_EQ(out[3].start_ns, 0);
  EXPECT_EQ(out[3].end_ns, 1600 * kMs);
  EXPECT_NEAR(zone(out[3], InclinationZone::Flexed), 0.4, kEps);
  EXPECT_NEAR(out[3].tracked_s, 1.6, kEps);
}

TEST(ExposureAccumulator, IntervalsAlignToTheGivenOffset) {
  ExposureOptions o = every(1000);
  o.align_ns = 300 * kMs;  // boundaries at 0.7 s, 1.7 s, …
  ExposureAccumulator acc(o);
  std::vector<Posture> postures;
  for (int i = 0; i < 20; ++i) postures.push_back(tracked(i * 100, 0));
  const auto out = run(acc, postures);
  ASSERT_EQ(out.size(), 6u);
  EXPECT_EQ(out[0].end_ns, 700 * kMs);
  EXPECT_TRUE(out[0].partial);
  EXPECT_EQ(out[2].start_ns, 700 * kMs);
  EXPECT_EQ(out[2].end_ns, 1700 * kMs);
  EXPECT_FALSE(out[2].partial);
  EXPECT_EQ(out[4].end_ns, 2000 * kMs);
  EXPECT_TRUE(out[4].partial);
}

TEST(ExposureAccumulator, CoverageSaysWhatEachFigureIsBasedOn) {
  ExposureAccumulator acc(every(10'000));  // max_gap 1 s
  const auto out = run(acc, {tracked(0, 0), untracked(200, TrackingState::Init, "learning_background"),
                             untracked(500, TrackingState::Lost), untracked(600, TrackingState::Lost, "no_person"),
                             tracked(1000, 30),
                             // 3.5 s without pairs: 1 s credited to the last, 2.5 s gap
                             tracked(4500, 30), tracked(5000, 30)});
  ASSERT_EQ(out.size(), 2u);
  const ExposureSummary& s = out[0];
  EXPECT_NEAR(s.tracked_s, 0.2 + 1.0 + 0.5 + 0.5, kEps);
  EXPECT_NEAR(s.init_s, 0.3, kEps);
  EXPECT_NEAR(s.lost_s, 0.1, kEps);
  EXPECT_NEAR(s.empty_s, 0.4, kEps);
  EXPECT_NEAR(s.gap_s, 2.5, kEps);
  EXPECT_NEAR(s.tracked_s + s.init_s + s.lost_s + s.empty_s + s.gap_s, s.duration_s(), kEps);
  EXPECT_NEAR(zone(s, InclinationZone::Flexed), 2.0, kEps);
}

TEST(ExposureAccumulator, LateralBendAndTwistEntriesAndTimeBeyondTenDegrees) {
  ExposureAccumulator acc(every(60'000));
  // Lateral: in at 1, 4, 6 (−20 counts as well); stays in at 2; out at 3, 5.
  // Twist: one entry (at 2), over for 0.2 s.
  const auto out = run(acc, {tracked(0, 0, 0, 0), tracked(100, 0, 15, 0), tracked(200, 0, 15, 12),
                             tracked(300, 0, 0, 12), tracked(400, 0, 12, 0), tracked(500, 0, 0, 0),
                             tracked(600, 0, -20, 0), untracked(700, TrackingState::Lost),
                             tracked(800, 0, -20, 0), tracked(900, 0, 0, 0)});
  const ExposureSummary& s = out[0];
  EXPECT_EQ(s.lateral_bend.entries, 3u);  // the lost pair does not make a new entry
  EXPECT_NEAR(s.lateral_bend.over_s, 0.5, kEps);
  EXPECT_EQ(s.axial_twist.entries, 1u);
  EXPECT_NEAR(s.axial_twist.over_s, 0.2, kEps);
  EXPECT_NEAR(s.lateral_bend.per_minute(s.tracked_s), 3 * 60 / 0.9, 1e-9);
}

// A twist held near the limit, fitted a step either side of it from pair to
// pair, is one entry (bend_twist_hysteresis_deg, 2°): back below 8° it ends.
// The time beyond counts the pairs beyond 10° only.
TEST(ExposureAccumulator, ATwistHeldAtTheLimitIsOneEntry) {
  const std::vector<Posture> stream = {tracked(0, 0, 0, 0),     tracked(100, 0, 0, 11), tracked(200, 0, 0, 9),
                                       tracked(300, 0, 0, 11),  tracked(400, 0, 0, 9),  tracked(500, 0, 0, 7),
                                       tracked(600, 0, 0, -11), tracked(700, 0, 0, 0)};
  ExposureAccumulator held(every(60'000));
  const ExposureSummary s = run(held, stream)[0];
  EXPECT_EQ(s.axial_twist.entries, 2u);
  EXPECT_NEAR(s.axial_twist.over_s, 0.3, kEps);
  ExposureOptions no_hysteresis = every(60'000);
  no_hysteresis.limits.bend_twist_hysteresis_deg = 0;
  ExposureAccumulator each_step(no_hysteresis);
  const ExposureSummary t = run(each_step, stream)[0];
  EXPECT_EQ(t.axial_twist.entries, 3u);
  EXPECT_NEAR(t.axial_twist.over_s, 0.3, kEps);
}

// A twist the fit could not resolve (its sign unknown) is counted by its
// magnitude like the rest, and its time apart, so the summary says what
// axial_twist rests on.
TEST(ExposureAccumulator, UnresolvedTwistTimeIsCountedApart) {
  ExposureAccumulator acc(every(60'000));
  auto unresolved = [](std::int64_t t_ms, double twist) {
    Posture p = tracked(t_ms, 0, 0, twist);
    p.fit.flag = std::string(kTwistUnresolvedFlag);
    return p;
  };
  Posture occluded = tracked(500, 0, 0, 0);
  occluded.fit.flag = "occluded";
  const auto out = run(acc, {tracked(0, 0, 0, 0), unresolved(100, 14), unresolved(200, 16), tracked(300, 0, 0, 15),
                             unresolved(400, 8), occluded, tracked(600, 0, 0, 0)});
  const ExposureSummary& s = out[0];
  EXPECT_NEAR(s.twist_unresolved_s, 0.3, kEps);
  EXPECT_EQ(s.axial_twist.entries, 1u);
  EXPECT_NEAR(s.axial_twist.over_s, 0.3, kEps);
  auto back = decode_summary(encode_summary(s), "line");
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_NEAR(back->summary.twist_unresolved_s, 0.3, 1e-3);
  // Summaries from before it was counted have none: read as 0.
  std::string old_line = encode_summary(s);
  const auto pos = old_line.find(",\"unresolved_s\":");
  ASSERT_NE(pos, std::string::npos);
  old_line.erase(pos, old_line.find('}', pos) - pos);
  auto old = decode_summary(old_line, "line");
  ASSERT_TRUE(old) << old.error().message;
  EXPECT_EQ(old->summary.twist_unresolved_s, 0.0);
}

TEST(ExposureAccumulator, HoldsBeyondTheLimitAndTheirTime) {
  ExposureOptions o = every(60'000);
  o.limits.inclination_max_hold_s = 0.5;
  ExposureAccumulator acc(o);
  std::vector<Posture> postures;
  std::int64_t t = 0;
  // 1.0 s at 30°: beyond the 0.5 s limit for 0.5 s.
  for (int i = 0; i < 10; ++i, t += 100) postures.push_back(tracked(t, 30));
  postures.push_back(tracked(t, 0));
  t += 100;
  // 0.4 s at 45°, a lost pair, 0.4 s at 45°: two holds, neither beyond.
  for (int i = 0; i < 4; ++i, t += 100) postures.push_back(tracked(t, 45));
  postures.push_back(untracked(t, TrackingState::Lost));
  t += 100;
  for (int i = 0; i < 4; ++i, t += 100) postures.push_back(tracked(t, 45));
  // 0.7 s at 70° (not the 20–60° zone) then 0.7 s at 50°: 0.2 s beyond.
  for (int i = 0; i < 7; ++i, t += 100) postures.push_back(tracked(t, 70));
  for (int i = 0; i < 7; ++i, t += 100) postures.push_back(tracked(t, 50));
  const auto out = run(acc, postures);
  const ExposureSummary& s = out[0];
  EXPECT_EQ(s.holds_beyond, 2u);
  EXPECT_NEAR(s.hold_beyond_s, 0.5 + 0.2, kEps);
  EXPECT_NEAR(s.longest_hold_s, 1.0, kEps);
  EXPECT_DOUBLE_EQ(s.hold_limit_s, 0.5);
}

TEST(ExposureAccumulator, LumbarCompressionPeakTimeAboveTheActionLimitAndCumulativeLoad) {
  ExposureAccumulator acc(every(60'000));
  const auto out = run(acc, {tracked(0, 0, 0, 0, 3000.0), tracked(250, 0, 0, 0, 3500.0),
                             tracked(500, 0, 0, 0, 4000.0), tracked(750, 0, 0, 0, 3000.0),
                             tracked(1000, 0)});  // no loads: not part of the compression figures
  const ExposureSummary& s = out[0];
  EXPECT_DOUBLE_EQ(s.compression_peak_n, 4000);
  EXPECT_NEAR(s.above_action_limit_s, 0.5, kEps);
  EXPECT_NEAR(s.cumulative_n_s, 0.25 * (3000 + 3500 + 4000 + 3000), 1e-6);
  EXPECT_NEAR(s.compression_based_on_s, 1.0, kEps);
  EXPECT_NEAR(s.compression_mean_n, 3375, 1e-6);
  EXPECT_NEAR(s.tracked_s, 1.25, kEps);
  EXPECT_DOUBLE_EQ(s.action_limit_n, 3400);
}

TEST(ExposureAccumulator, AClockThatGoesBackStartsANewShift) {
  ExposureAccumulator acc(every(60'000));
  std::vector<ExposureSummary> out;
  for (auto t : {0, 100, 200}) EXPECT_TRUE(acc.add(tracked(t, 30)).empty());
  auto closed = acc.add(tracked(50, 0));  // went back
  ASSERT_EQ(closed.size(), 2u);
  EXPECT_NEAR(closed[1].tracked_s, 0.3, kEps);
  EXPECT_NEAR(zone(closed[1], InclinationZone::Flexed), 0.3, kEps);
  acc.add(tracked(150, 0));
  const auto last = acc.finish();
  ASSERT_EQ(last.size(), 2u);
  EXPECT_EQ(last[1].start_ns, 50 * kMs);
  EXPECT_NEAR(zone(last[1], InclinationZone::Upright), 0.2, kEps);
  EXPECT_NEAR(zone(last[1], InclinationZone::Flexed), 0.0, kEps);
}

TEST(SummaryJson, RoundTripsAndValidatesAgainstTheSchema) {
  ExposureOptions o = every(1000);
  ExposureAccumulator acc(o);
  std::vector<Posture> postures;
  for (int i = 0; i < 25; ++i) postures.push_back(tracked(i * 100, i * 4.0 - 10, i % 3 ? 12 : 0, 0, 3000 + 50.0 * i));
  postures.push_back(untracked(2500, TrackingState::Lost, "no_person"));
  const auto out = run(acc, postures);
  ASSERT_EQ(out.size(), 6u);
  SummaryLabels labels{.station = "bench 3", .worker = "w-17", .utc_offset_ns = 1'764'661'200'000'000'000};
  test::TempDir dir;
  {
    std::ofstream f(dir / "summaries.ndjson");
    for (const auto& s : out) f << encode_summary(s, labels) << '\n';
  }
  EXPECT_EQ(test::validate_ndjson(dir / "summaries.ndjson"), "");
  for (const auto& s : out) {
    auto back = decode_summary(encode_summary(s, labels), "line");
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back->summary.start_ns, s.start_ns);
    EXPECT_EQ(back->summary.end_ns, s.end_ns);
    EXPECT_EQ(back->summary.scope, s.scope);
    for (std::size_t z = 0; z < kInclinationZoneCount; ++z) EXPECT_NEAR(back->summary.zone_s[z], s.zone_s[z], 1e-6);
    EXPECT_EQ(back->summary.lateral_bend.entries, s.lateral_bend.entries);
    EXPECT_NEAR(back->summary.cumulative_n_s, s.cumulative_n_s, 0.051);
    EXPECT_EQ(back->labels.worker, "w-17");
    EXPECT_EQ(back->labels.station, "bench 3");
    ASSERT_TRUE(back->utc_start_ns());
    EXPECT_EQ(*back->utc_start_ns() / kMs, (s.start_ns + *labels.utc_offset_ns) / kMs);
  }
  EXPECT_NE(encode_summary(out[0], labels).find("\"utc_start\":\"2025-12-02T"), std::string::npos);
}

TEST(SummaryJson, BadLinesNameTheField) {
  ExposureAccumulator acc(every(1000));
  const auto out = run(acc, {tracked(0, 0), tracked(100, 0)});
  std::string line = encode_summary(out[0]);
  const auto pos = line.find("\"tracked_s\":");
  line.replace(pos, std::string("\"tracked_s\":").size(), "\"tracked_s\":\"x\",\"was\":");
  auto bad = decode_summary(line, "f.ndjson:3");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "f.ndjson:3: coverage/tracked_s: expected a number");
  EXPECT_FALSE(decode_summary("{\"class\":\"posture\"}", "x"));
  EXPECT_FALSE(decode_summary("not json", "x"));
}

TEST(Utc, FormatsAndParses) {
  EXPECT_EQ(format_utc(0), "1970-01-01T00:00:00.000Z");
  EXPECT_EQ(format_utc(1'764'662'100'250'000'000), "2025-12-02T07:55:00.250Z");
  EXPECT_EQ(*parse_utc("2025-12-02T07:55:00.250Z"), 1'764'662'100'250'000'000);
  EXPECT_EQ(*parse_utc("2025-12-02T07:55:00Z"), 1'764'662'100'000'000'000);
  EXPECT_FALSE(parse_utc("2025-12-02 07:55"));
  EXPECT_FALSE(parse_utc("2025-13-02T07:55:00Z"));
}

}  // namespace
}  // namespace spinewatch
