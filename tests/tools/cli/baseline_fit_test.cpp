// scripts/baseline-fit (docs/accuracy.md, "Today's fit on the varied
// phantom") in its smallest form: one test-set subject, one limb scenario,
// a few frames, both fit modes. The table must keep its shape, its cells
// must be numbers, and the numbers must be those of the posture files it
// wrote — so the script cannot rot unnoticed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <regex>
#include <sstream>

#include "test_support.hpp"

namespace spinewatch {
namespace {

constexpr int kSubject = 28496;  // ANSUR II test set (docs/anthropometry.md, "Train / test split")
constexpr int kTrainingSubject = 10027;  // the first man of the release: a training subject
// Enough person frames that the subject model (10 upright pairs) is built
// and a few pairs are tracked in both modes.
constexpr int kFrames = 14;

std::string script_command(const std::string& args) {
  return "cd '" + test::source_dir() + "' && /usr/bin/python3 scripts/baseline-fit --spinewatch '" + test::cli_path() +
         "' " + args;
}

std::vector<std::string> split_row(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  std::getline(in, cell, '|');  // before the first bar
  while (std::getline(in, cell, '|')) {
    const auto first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
    cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
  }
  if (!cells.empty() && cells.back().empty()) cells.pop_back();  // after the last bar
  return cells;
}

struct Measured {
  std::map<std::string, int> states;
  int person_frames = 0;
  double worst = 0;
  int wrong = 0;
};

// What the table's state and worst-posture cells must say, from the files.
Measured measure(const std::filesystem::path& recording, const std::filesystem::path& postures) {
  std::map<std::uint64_t, nlohmann::json> truth;
  for (auto& t : test::read_ndjson(recording / "ground_truth.ndjson"))
    if (t.at("state") != "lost") truth[t.at("seq").get<std::uint64_t>()] = t;
  Measured m;
  m.person_frames = int(truth.size());
  for (const auto& p : test::read_ndjson(postures)) {
    auto it = truth.find(p.at("seq").get<std::uint64_t>());
    if (it == truth.end()) continue;
    ++m.states[p.at("state").get<std::string>()];
    if (p.at("state") != "tracking") continue;
    double worst = 0;
    for (std::size_t i = 0; i < 17; ++i) {
      const auto& a = p.at("vertebrae").at(i).at("body_center");
      const auto& b = it->second.at("vertebrae").at(i).at("body_center");
      worst = std::max(worst, std::hypot(a[0].get<double>() - b[0].get<double>(), a[1].get<double>() - b[1].get<double>(),
                                         a[2].get<double>() - b[2].get<double>()));
    }
    m.worst = std::max(m.worst, worst);
    m.wrong += worst > 50;
  }
  return m;
}

TEST(BaselineFit, ATinyRunPrintsTheRowOfBothModesFromItsPostures) {
  test::TempDir dir;
  const auto table = dir / "table.md";
  auto r = test::run_command(script_command("--work '" + dir.path().string() + "' --subjects " +
                                            std::to_string(kSubject) + " --rows carry --frames " +
                                            std::to_string(kFrames) + " > '" + table.string() + "'"));
  ASSERT_EQ(r.exit_code, 0) << r.output << test::read_file(table);
  const std::string text = test::read_file(table);

  std::vector<std::vector<std::string>> rows;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("| ", 0) == 0) rows.push_back(split_row(line));
  ASSERT_EQ(rows.size(), 4u) << "a header and the one row, twice (the trunk angles' table):\n" << text;
  const std::vector<std::string> per_mode = {"neck", "waist", "vertebrae", "tracking / init / lost %",
                                             "worst tracking (> 50 mm)"};
  ASSERT_EQ(rows[0].size(), 11u) << text;
  EXPECT_EQ(rows[0][0], "scenario / option");
  for (std::size_t i = 0; i < per_mode.size(); ++i) {
    EXPECT_EQ(rows[0][1 + i], "fixed: " + per_mode[i]);
    EXPECT_EQ(rows[0][6 + i], "articulated: " + per_mode[i]);
  }
  const auto& row = rows[1];
  ASSERT_EQ(row.size(), 11u) << text;
  EXPECT_EQ(row[0], "`carry`");
  EXPECT_NE(text.find("28496"), std::string::npos) << "the subject is named:\n" << text;

  const std::regex millimetres(R"(\d+\.\d)"), shares(R"((\d+) / (\d+) / (\d+))"), worst(R"((\d+) \((\d+)\))");
  const std::string modes[] = {"fixed", "articulated"};
  for (int m = 0; m < 2; ++m) {
    SCOPED_TRACE(modes[m]);
    const std::size_t c = 1 + 5 * std::size_t(m);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_TRUE(std::regex_match(row[c + i], millimetres)) << row[c + i];
    const Measured truth = measure(dir / "carry" / std::to_string(kSubject) / "recording",
                                   dir / "carry" / std::to_string(kSubject) / (modes[m] + ".ndjson"));
    ASSERT_EQ(truth.person_frames, kFrames);
    ASSERT_GT(truth.states.count("tracking"), 0u) << "no pair tracked: the cells would be empty";
    std::smatch s;
    ASSERT_TRUE(std::regex_match(row[c + 3], s, shares)) << row[c + 3];
    int sum = 0;
    const char* states[] = {"tracking", "init", "lost"};
    for (int k = 0; k < 3; ++k) {
      const int share = std::stoi(s[1 + k]);
      sum += share;
      const double expected = 100.0 * (truth.states.count(states[k]) ? truth.states.at(states[k]) : 0) / kFrames;
      EXPECT_NEAR(share, expected, 0.51) << states[k];
    }
    EXPECT_NEAR(sum, 100, 2);
    std::smatch w;
    ASSERT_TRUE(std::regex_match(row[c + 4], w, worst)) << row[c + 4];
    EXPECT_NEAR(std::stod(w[1]), truth.worst, 0.51);
    EXPECT_EQ(std::stoi(w[2]), truth.wrong);
  }

  // The trunk angles' table: per mode inclination and side bend, each
  // "mean / max; wrong side of bent", as eval's JSON of the same replay says.
  ASSERT_EQ(rows[2].size(), 5u) << text;
  EXPECT_EQ(rows[2][1], "fixed: inclination: mean / max error °; wrong side of bent");
  EXPECT_EQ(rows[2][4], "articulated: side bend: mean / max error °; wrong side of bent");
  ASSERT_EQ(rows[3].size(), 5u) << text;
  EXPECT_EQ(rows[3][0], "`carry`");
  const std::regex angle(R"((\d+\.\d) / (\d+\.\d); (\d+) of (\d+))");
  for (int m = 0; m < 2; ++m) {
    const auto eval = nlohmann::json::parse(
        test::read_file(dir / "carry" / std::to_string(kSubject) / (modes[m] + ".eval.json")));
    const char* keys[] = {"inclination_deg", "side_bend_deg"};
    for (int k = 0; k < 2; ++k) {
      SCOPED_TRACE(modes[m] + " " + keys[k]);
      std::smatch a;
      ASSERT_TRUE(std::regex_match(rows[3][1 + 2 * m + k], a, angle)) << rows[3][1 + 2 * m + k];
      const auto& e = eval.at(keys[k]);
      EXPECT_NEAR(std::stod(a[1]), e.at("mean").get<double>(), 0.051);
      EXPECT_NEAR(std::stod(a[2]), e.at("max").get<double>(), 0.051);
      EXPECT_EQ(std::stoi(a[3]), e.at("wrong_side").get<int>());
      EXPECT_EQ(std::stoi(a[4]), e.at("bent_frames").get<int>());
    }
  }
}

TEST(BaselineFit, RefusesTrainingSubjectsAndUnknownRows) {
  auto training = test::run_command(script_command("--subjects " + std::to_string(kTrainingSubject) + " --rows reach"));
  EXPECT_EQ(training.exit_code, 2) << training.output;
  EXPECT_NE(training.output.find("10027 is a training subject"), std::string::npos) << training.output;
  auto row = test::run_command(script_command("--rows flexion,sideways"));
  EXPECT_EQ(row.exit_code, 2) << row.output;
  EXPECT_NE(row.output.find("unknown row 'sideways'"), std::string::npos) << row.output;
}

// --modes takes [cvsm] limbs values, each once.
TEST(BaselineFit, RefusesUnknownOrRepeatedLimbModes) {
  for (const char* modes : {"fixed,loose", "auto,auto", ","}) {
    auto r = test::run_command(script_command(std::string("--modes '") + modes + "' --rows flexion"));
    EXPECT_EQ(r.exit_code, 2) << modes << ": " << r.output;
    EXPECT_NE(r.output.find("give distinct [cvsm] limbs values among fixed, articulated, auto"), std::string::npos)
        << r.output;
  }
}

}  // namespace
}  // namespace spinewatch
