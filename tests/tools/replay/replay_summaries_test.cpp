// spinewatch replay --summaries: the exposure summaries of a recording,
// offline (docs/exposure.md), their length from [exposure] interval_s.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace spinewatch {
namespace {

using test::read_ndjson;

TEST(ReplaySummaries, IntervalsOfTheConfiguredLengthThenTheShiftValidAgainstTheSchema) {
  test::TempDir dir;
  // 90 person frames after 10 empty ones: 3.33 s; flexion 0 → 50° → 0.
  auto r = test::run_cli("phantom --subject generic --scenario flexion --frames 90 --seed 3 --out " + (dir / "rec").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::map<int, std::vector<nlohmann::json>> by_interval;
  for (const std::string interval_s : {"1", "2"}) {
    const auto config = dir / (interval_s + ".toml");
    test::write_file(config, "[subject]\nspine_placement = \"generic\"\n[exposure]\ninterval_s = " + interval_s + "\n");
    const auto summaries = dir / (interval_s + ".ndjson");
    auto replay = test::run_cli("replay --recording " + (dir / "rec").string() + " --config " + config.string() +
                                " --out " + (dir / "p.ndjson").string() + " --summaries " + summaries.string());
    ASSERT_EQ(replay.exit_code, 0) << replay.output;
    EXPECT_EQ(test::validate_ndjson(summaries), "");
    by_interval[std::stoi(interval_s)] = read_ndjson(summaries);
    // --out keeps posture lines only (docs/interfaces.md §3).
    for (const auto& p : read_ndjson(dir / "p.ndjson")) ASSERT_EQ(p.at("class"), "posture");
  }
  // 3.33 s: [0,1) [1,2) [2,3) [3,3.33) with 1 s; [0,2) [2,3.33) with 2 s; each with the shift.
  ASSERT_EQ(by_interval[1].size(), 8u);
  ASSERT_EQ(by_interval[2].size(), 4u);
  const auto& shift1 = by_interval[1].back();
  const auto& shift2 = by_interval[2].back();
  EXPECT_EQ(shift1.at("scope"), "shift");
  EXPECT_NEAR(shift1.at("duration_s").get<double>(), 100.0 / 30.0, 1e-6);
  // The same recording summed either way.
  for (const char* zone : {"extension", "0_20", "20_60", "over_60"})
    EXPECT_NEAR(shift1.at("trunk_inclination").at("zones_s").at(zone).get<double>(),
                shift2.at("trunk_inclination").at("zones_s").at(zone).get<double>(), 1e-5)
        << zone;
  // The bend goes past 20° (0.67 of the 50° whole-trunk flexion is the L5→T1 line's).
  EXPECT_GT(shift1.at("trunk_inclination").at("zones_s").at("20_60").get<double>(), 0.5);
  EXPECT_GT(shift1.at("trunk_inclination").at("max_deg").get<double>(), 25.0);
  // The empty frames first: not tracked, and said so.
  const auto& first = by_interval[1].front().at("coverage");
  EXPECT_GT(first.at("empty_s").get<double>() + first.at("init_s").get<double>(), 0.3);
  EXPECT_GT(shift1.at("lumbar_compression").at("peak_n").get<double>(), 400.0);

  auto both = test::run_cli("replay --recording " + (dir / "rec").string() + " --out - --summaries -");
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_NE(both.output.find("--summaries -"), std::string::npos) << both.output;
}

}  // namespace
}  // namespace spinewatch
