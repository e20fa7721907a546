// scripts/cross-pair-phantom (docs/accuracy.md, "The same instant from
// different camera pairs") in its smallest form: one test-set subject, one
// scenario, a few frames. Its row must be the comparison of the posture
// files it wrote: T1 and L5 of every two renders' tracking postures of the
// same frame, so the script cannot rot unnoticed.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>
#include <vector>

#include "test_support.hpp"

// A namespace of its own: the unity build joins this file with
// baseline_fit_test.cpp, whose helpers have the same names.
namespace spinewatch::cross_pair {
namespace {

constexpr int kSubject = 28496;  // ANSUR II test set (docs/anthropometry.md, "Train / test split")
constexpr int kFrames = 14;      // the subject model (10 pairs) built, a few pairs tracked
constexpr int kGeometries = 4;

std::string script_command(const std::string& args) {
  return "cd '" + test::source_dir() + "' && /usr/bin/python3 scripts/cross-pair-phantom --spinewatch '" +
         test::cli_path() + "' " + args;
}

using Point = std::array<double, 3>;
struct Tracked {
  Point t1, l5;
};

std::map<std::uint64_t, Tracked> tracked(const std::filesystem::path& postures) {
  std::map<std::uint64_t, Tracked> out;
  for (const auto& p : test::read_ndjson(postures)) {
    if (p.at("state") != "tracking" || p.at("neck").is_null()) continue;
    const auto point = [&](const char* key) {
      const auto& v = p.at(key);
      return Point{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
    };
    out[p.at("seq").get<std::uint64_t>()] = {point("neck"), point("waist")};
  }
  return out;
}

double distance(const Point& a, const Point& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

TEST(CrossPairPhantom, ATinyRunComparesEveryTwoRendersOfTheSameFrame) {
  test::TempDir dir;
  const auto table = dir / "table.md";
  auto r = test::run_command(script_command("--work '" + dir.path().string() + "' --subjects " +
                                            std::to_string(kSubject) + " --scenarios flexion --frames " +
                                            std::to_string(kFrames) + " > '" + table.string() + "'"));
  ASSERT_EQ(r.exit_code, 0) << r.output << test::read_file(table);
  const std::string text = test::read_file(table);

  // What the row must say, from the posture files.
  std::vector<std::map<std::uint64_t, Tracked>> renders;
  for (int g = 0; g < kGeometries; ++g)
    renders.push_back(tracked(dir / "flexion" / std::to_string(kSubject) / std::to_string(g) / "postures.ndjson"));
  std::vector<double> t1, l5;
  int within = 0;
  for (int a = 0; a < kGeometries; ++a)
    for (int b = a + 1; b < kGeometries; ++b)
      for (const auto& [seq, p] : renders[std::size_t(a)]) {
        const auto q = renders[std::size_t(b)].find(seq);
        if (q == renders[std::size_t(b)].end()) continue;
        t1.push_back(distance(p.t1, q->second.t1));
        l5.push_back(distance(p.l5, q->second.l5));
        within += t1.back() <= 20 && l5.back() <= 20;
      }
  ASSERT_FALSE(t1.empty()) << "no frame tracked by two renders:\n" << text;

  const std::regex row(R"(\| `flexion` \| (\d+) \| ([\d.]+) / ([\d.]+) / ([\d.]+) \| ([\d.]+) / ([\d.]+) / ([\d.]+) \| (\d+) % \|)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, row)) << text;
  EXPECT_EQ(std::stoul(m[1]), t1.size());
  EXPECT_NEAR(std::stod(m[4]), *std::max_element(t1.begin(), t1.end()), 0.051);
  EXPECT_NEAR(std::stod(m[7]), *std::max_element(l5.begin(), l5.end()), 0.051);
  EXPECT_NEAR(std::stod(m[8]), 100.0 * within / double(t1.size()), 0.51);
}

TEST(CrossPairPhantom, RefusesTrainingSubjects) {
  auto training = test::run_command(script_command("--subjects 10027"));
  EXPECT_EQ(training.exit_code, 2) << training.output;
  EXPECT_NE(training.output.find("10027 is a training subject"), std::string::npos) << training.output;
}

}  // namespace
}  // namespace spinewatch::cross_pair
