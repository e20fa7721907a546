#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "ops/config_reload.hpp"
#include "publish/stream_lines.hpp"
#include "spinewatch/estimator/posture_json.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

Posture tracking_posture() { return test::sample_tracking_posture(); }

TEST(StreamLines, HelloAndPostureLinesValidateAgainstTheSchemas) {
  test::TempDir dir;
  const std::string hello = make_hello_line("desk-3", CameraRig::default_rig(), "recording /tmp/x");
  const std::string line = encode_posture_line(tracking_posture(), StreamStats{42, 3, 7, 2, 1});
  Posture lost;
  lost.seq = 42;
  const std::string lost_line = encode_posture_line(lost, StreamStats{43, 3, 7, 2, 1});
  test::write_file(dir / "stream.ndjson", hello + "\n" + line + "\n" + lost_line + "\n");
  EXPECT_EQ(test::validate_ndjson(dir / "stream.ndjson"), "");

  const auto h = nlohmann::json::parse(hello);
  EXPECT_EQ(h.at("class"), "hello");
  EXPECT_EQ(h.at("v"), 1);
  EXPECT_EQ(h.at("station"), "desk-3");
  EXPECT_EQ(h.at("source"), "recording /tmp/x");
  EXPECT_DOUBLE_EQ(h.at("rig").at("frontal").at("camera_matrix")[0][0].get<double>(),
                   CameraRig::default_rig().frontal.camera_matrix(0, 0));
  EXPECT_EQ(h.at("rig").at("lateral").at("t").size(), 3u);
}

TEST(StreamLines, StatsAreIntegersAndThePostureIsUnchanged) {
  const Posture p = tracking_posture();
  const auto j = nlohmann::json::parse(encode_posture_line(p, StreamStats{42, 3, 7, 2, 1}));
  const auto& s = j.at("stats");
  EXPECT_EQ(s.at("pairs"), 42);
  EXPECT_EQ(s.at("pairs_dropped"), 3);
  EXPECT_EQ(s.at("frames_lost"), 7);
  EXPECT_EQ(s.at("clients"), 2);
  EXPECT_EQ(s.at("clients_dropped"), 1);
  for (const auto& [k, v] : s.items()) EXPECT_TRUE(v.is_number_unsigned()) << k;
  auto without = j;
  without.erase("stats");
  EXPECT_EQ(without, nlohmann::json::parse(encode_posture(p)));
}

TEST(ConfigReload, ComparesEveryKeyTheLoaderKnows) {
  auto compared = compared_keys();
  auto known = config_keys();
  std::sort(compared.begin(), compared.end());
  std::sort(known.begin(), known.end());
  EXPECT_EQ(compared, known);
}

TEST(ConfigReload, NamesChangedKeysAndWhichNeedARestart) {
  Config a, b;
  EXPECT_TRUE(changed_keys(a, b).empty());
  b.station.name = "desk-7";
  b.log.level = LogLevel::Debug;
  b.publish.listen = "0.0.0.0:7117";
  b.cameras.fps = 60;
  const auto changed = changed_keys(a, b);
  EXPECT_EQ(changed, (std::vector<std::string>{"station.name", "cameras.fps", "publish.listen", "log.level"}));
  EXPECT_TRUE(reloadable_key("station.name"));
  EXPECT_TRUE(reloadable_key("log.level"));
  EXPECT_FALSE(reloadable_key("publish.listen"));
  EXPECT_FALSE(reloadable_key("cameras.fps"));
}

}  // namespace
}  // namespace spinewatch
