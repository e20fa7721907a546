// spinewatch export: a phantom replay's postures as OpenSim spine.mot and
// spine.trc, read back with a small parser of this test's own (not the
// writer's code), and compared with the posture lines they came from
// (docs/exposure.md, "Export for researchers").
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "storage/store.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

std::vector<std::string> split_tabs(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, '\t')) out.push_back(cell);
  if (!line.empty() && line.back() == '\t') out.emplace_back();
  return out;
}

std::vector<std::string> lines_of(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

struct Mot {
  std::map<std::string, std::string> header;
  std::string name;
  std::vector<std::string> labels;
  std::vector<std::vector<double>> rows;
};

Mot parse_mot(const std::filesystem::path& path) {
  Mot m;
  const auto lines = lines_of(path);
  std::size_t i = 0;
  m.name = lines.at(i++);
  for (; i < lines.size() && lines[i] != "endheader"; ++i) {
    const auto eq = lines[i].find('=');
    if (eq != std::string::npos) m.header[lines[i].substr(0, eq)] = lines[i].substr(eq + 1);
  }
  m.labels = split_tabs(lines.at(++i));
  for (++i; i < lines.size(); ++i) {
    std::vector<double> row;
    for (const auto& c : split_tabs(lines[i])) row.push_back(std::stod(c));
    m.rows.push_back(row);
  }
  return m;
}

struct Trc {
  std::vector<std::string> first;
  std::map<std::string, std::string> header;
  std::vector<std::string> markers;
  std::vector<std::vector<double>> rows;
};

Trc parse_trc(const std::filesystem::path& path) {
  Trc t;
  const auto lines = lines_of(path);
  t.first = split_tabs(lines.at(0));
  const auto keys = split_tabs(lines.at(1)), values = split_tabs(lines.at(2));
  for (std::size_t k = 0; k < keys.size(); ++k) t.header[keys[k]] = values.at(k);
  const auto names = split_tabs(lines.at(3));
  EXPECT_EQ(names.at(0), "Frame#");
  EXPECT_EQ(names.at(1), "Time");
  for (std::size_t k = 2; k < names.size(); ++k)
    if (!names[k].empty()) {
      EXPECT_EQ((k - 2) % 3, 0u) << "each marker's name heads its X column";
      t.markers.push_back(names[k]);
    }
  EXPECT_EQ(split_tabs(lines.at(4)).at(2), "X1");
  EXPECT_TRUE(lines.at(5).empty()) << "a blank line before the data";
  for (std::size_t i = 6; i < lines.size(); ++i) {
    std::vector<double> row;
    for (const auto& c : split_tabs(lines[i])) row.push_back(std::stod(c));
    t.rows.push_back(row);
  }
  return t;
}

std::vector<nlohmann::json> tracked_postures(const std::filesystem::path& path, double from_s = -1e300,
                                             double to_s = 1e300) {
  std::vector<nlohmann::json> out;
  for (const auto& l : lines_of(path)) {
    auto j = nlohmann::json::parse(l);
    const double t = j.at("t_ns").get<double>() / 1e9;
    if (j.at("state") == "tracking" && t >= from_s && t < to_s) out.push_back(j);
  }
  return out;
}

class Export : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    // 10 empty frames (lost), the model being built (init), then a 0 → 50° flexion: 3.33 s.
    auto r = test::run_cli("phantom --subject generic --scenario flexion --frames 90 --seed 3 --out " + (*dir_ / "rec").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto replay = test::run_cli("replay --recording " + (*dir_ / "rec").string() + " --out " + postures().string());
    ASSERT_EQ(replay.exit_code, 0) << replay.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::filesystem::path postures() { return *dir_ / "p.ndjson"; }
  static test::TempDir* dir_;
};
test::TempDir* Export::dir_ = nullptr;

TEST_F(Export, MarkersAndAnglesReadBackEqualThePostureLines) {
  const auto out = *dir_ / "all";
  auto r = test::run_cli("export --postures " + postures().string() + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto expected = tracked_postures(postures());
  const std::size_t all_lines = lines_of(postures()).size();
  ASSERT_GT(expected.size(), 60u);
  ASSERT_LT(expected.size(), all_lines) << "the scenario starts with lost and init pairs, which are omitted";

  const Trc trc = parse_trc(out / "spine.trc");
  EXPECT_EQ(trc.first.at(0), "PathFileType");
  EXPECT_EQ(trc.first.at(1), "4");
  EXPECT_EQ(trc.first.at(2), "(X/Y/Z)");
  EXPECT_EQ(trc.header.at("Units"), "mm");
  EXPECT_EQ(std::stoul(trc.header.at("NumFrames")), expected.size());
  EXPECT_EQ(std::stoul(trc.header.at("NumMarkers")), 17u);
  EXPECT_NEAR(std::stod(trc.header.at("DataRate")), 30.0, 0.01);
  EXPECT_EQ(trc.header.at("CameraRate"), trc.header.at("DataRate"));
  const std::vector<std::string> names = {"T1", "T2", "T3", "T4", "T5", "T6", "T7", "T8", "T9",
                                          "T10", "T11", "T12", "L1", "L2", "L3", "L4", "L5"};
  EXPECT_EQ(trc.markers, names);
  ASSERT_EQ(trc.rows.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const auto& row = trc.rows[i];
    ASSERT_EQ(row.size(), 2 + 3 * 17u);
    EXPECT_EQ(row[0], double(i + 1));
    EXPECT_NEAR(row[1], expected[i].at("t_ns").get<double>() / 1e9, 0.5e-6 + 1e-12);
    const auto& v = expected[i].at("vertebrae");
    for (std::size_t k = 0; k < 17; ++k)
      for (std::size_t a = 0; a < 3; ++a)  // written with 3 decimals: within half a micrometre
        ASSERT_NEAR(row[2 + 3 * k + a], v[k].at("body_center")[a].get<double>(), 0.5e-3 + 1e-9)
            << "row " << i << " " << names[k] << " axis " << a;
  }

  const Mot mot = parse_mot(out / "spine.mot");
  EXPECT_EQ(mot.header.at("version"), "1");
  EXPECT_EQ(mot.header.at("inDegrees"), "yes");
  EXPECT_EQ(std::stoul(mot.header.at("nRows")), expected.size());
  EXPECT_EQ(std::stoul(mot.header.at("nColumns")), mot.labels.size());
  ASSERT_EQ(mot.labels.size(), 1 + 17 * 3u);
  EXPECT_EQ(mot.labels[0], "time");
  EXPECT_EQ(mot.labels[1], "L5_flex");
  EXPECT_EQ(mot.labels[4], "L4_L5_flex");
  EXPECT_EQ(mot.labels.back(), "T1_T2_rot");
  ASSERT_EQ(mot.rows.size(), expected.size());
  std::map<std::string, std::size_t> column;
  for (std::size_t c = 0; c < mot.labels.size(); ++c) column[mot.labels[c]] = c;
  constexpr double kAngleTolerance = 0.005 + 0.001;
  double max_flex = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const auto& row = mot.rows[i];
    ASSERT_EQ(row.size(), mot.labels.size());
    EXPECT_NEAR(row[0], trc.rows[i][1], 1e-9);
    // Intervertebral angles: the posture line's own "angles" (T1-T2 → T1_T2_*). The line rounds them
    // to 0.01°; the export computes them from the line's quaternions and writes 4 decimals.
    for (const auto& level : expected[i].at("angles")) {
      std::string key = level.at("level").get<std::string>();
      key[key.find('-')] = '_';
      EXPECT_NEAR(row[column.at(key + "_flex")], level.at("flexion").get<double>(), kAngleTolerance) << key;
      EXPECT_NEAR(row[column.at(key + "_lat")], level.at("lateral").get<double>(), kAngleTolerance) << key;
      EXPECT_NEAR(row[column.at(key + "_rot")], level.at("twist").get<double>(), kAngleTolerance) << key;
      max_flex = std::max(max_flex, row[column.at(key + "_flex")]);
    }
    // L5 in the world: Rz(−flex)·Rx(lat)·Ry(rot) (kinematics.hpp's convention) rebuilds its quaternion.
    const double d = M_PI / 180;
    const Eigen::Quaterniond rebuilt = Eigen::AngleAxisd(-row[1] * d, Eigen::Vector3d::UnitZ()) *
                                       Eigen::AngleAxisd(row[2] * d, Eigen::Vector3d::UnitX()) *
                                       Eigen::AngleAxisd(row[3] * d, Eigen::Vector3d::UnitY());
    const auto& q = expected[i].at("vertebrae")[16].at("q");
    const Eigen::Quaterniond l5(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>());
    EXPECT_LT(rebuilt.angularDistance(l5.normalized()) / d, 1e-3) << "row " << i;
  }
  EXPECT_GT(max_flex, 1.0) << "the flexion scenario bends the joints forward";
}

TEST_F(Export, TimeRangeSelectsRowsAndBadInputIsOneClearMessage) {
  const auto out = *dir_ / "range";
  auto r = test::run_cli("export --postures " + postures().string() + " --from 1.5 --to 2.5 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto expected = tracked_postures(postures(), 1.5, 2.5);
  const Mot mot = parse_mot(out / "spine.mot");
  ASSERT_EQ(mot.rows.size(), expected.size());
  EXPECT_GE(mot.rows.front()[0], 1.5);
  EXPECT_LT(mot.rows.back()[0], 2.5);
  EXPECT_EQ(std::stoul(parse_trc(out / "spine.trc").header.at("NumFrames")), expected.size());

  auto utc = test::run_cli("export --postures " + postures().string() + " --from 2026-12-02T08:00:00Z --out " +
                           (*dir_ / "utc").string());
  EXPECT_EQ(utc.exit_code, 1);
  EXPECT_NE(utc.output.find("posture lines carry no UTC time"), std::string::npos) << utc.output;
  auto none = test::run_cli("export --postures " + postures().string() + " --from 100 --out " + (*dir_ / "n").string());
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_NE(none.output.find("no tracked posture in the range"), std::string::npos) << none.output;
  auto both = test::run_cli("export --out " + (*dir_ / "b").string());
  EXPECT_EQ(both.exit_code, 2) << both.output;
  test::write_file(*dir_ / "bad.ndjson", "{\"class\": \"posture\", \"v\": 1, \"seq\": 1}\n");
  auto bad = test::run_cli("export --postures " + (*dir_ / "bad.ndjson").string() + " --out " + (*dir_ / "x").string());
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("bad.ndjson:1: t_ns"), std::string::npos) << bad.output;
}

TEST_F(Export, FromTheStationsDatabaseTheStoredPosturesOnly) {
  // The daemon stores every storage.posture_every-th posture line: here every third.
  const auto db = *dir_ / "station.db";
  std::size_t stored_tracked = 0;
  {
    Store store(StoreOptions{.path = db});
    for (const auto& line : lines_of(postures())) {
      const auto j = nlohmann::json::parse(line);
      if (j.at("seq").get<std::uint64_t>() % 3 != 0) continue;
      store.add_posture(j.at("seq"), j.at("t_ns"), line);
      if (j.at("state") == "tracking") ++stored_tracked;
      store.add_alert(j.at("t_ns"), "{\"class\": \"alert\"}");  // other tables are not read
    }
    store.stop();
    ASSERT_EQ(store.stats().failed, 0u);
  }
  const auto out = *dir_ / "db";
  auto r = test::run_cli("export --db " + db.string() + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Trc trc = parse_trc(out / "spine.trc");
  EXPECT_EQ(trc.rows.size(), stored_tracked);
  EXPECT_NEAR(std::stod(trc.header.at("DataRate")), 10.0, 0.01) << "30 fps, every third stored";
  // UTC bounds compare with when the rows were stored: all of them are from just now.
  auto utc = test::run_cli("export --db " + db.string() + " --from 2000-01-01T00:00:00Z --out " + (out / "u").string());
  ASSERT_EQ(utc.exit_code, 0) << utc.output;
  EXPECT_EQ(parse_mot(out / "u" / "spine.mot").rows.size(), stored_tracked);
  auto future = test::run_cli("export --db " + db.string() + " --from 2100-01-01T00:00:00Z --out " + (out / "f").string());
  EXPECT_EQ(future.exit_code, 1) << future.output;
}

}  // namespace
}  // namespace spinewatch
