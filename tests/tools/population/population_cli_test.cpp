// spinewatch population as a user runs it: bad input is one clear message
// and a non-zero exit (2 for a bad option value, 1 for what is wrong
// with the data or the selection); a small sweep prints its tables, and
// --known-worker says so in the pooled title.
#include <gtest/gtest.h>

#include "spinewatch/anthropometry/ansur.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

// The data wherever the test runs from (the command's default is relative
// to the repository's parent), unless the case names its own.
std::string population_command(std::string_view args = "") {
  if (args.rfind("--ansur", 0) == 0) return "--log-level warn population ";
  return "--log-level warn population --ansur '" +
         test::source_path(std::string(anthropometry::kAnsurRelativeDir)).string() + "' ";
}

struct Case {
  const char* args;
  int exit_code;
  const char* message;
};

TEST(PopulationCli, BadInputIsOneClearMessage) {
  const Case cases[] = {
      {"--scenarios ''", 2, "--scenarios: no scenario given"},
      {"--set both", 2, "--set: both not in {test,train}"},
      {"--rules both", 2, "--rules: both not in {drawn,mean}"},
      {"--men -1", 2, "--men: Value -1 not in range 0 to 1000"},
      {"--refine-steps 5", 2, "--refine-steps: Value 5 not in range 0 to 4"},
      {"--ansur /nonexistent", 1, "/nonexistent/ANSUR_II_MALE_Public.csv: cannot open"},
      {"--men 0 --women 0", 1, "population: no subject matches the selection"},
      {"--men 1 --women 0 --scenarios dance", 1, "unknown scenario \"dance\""},
  };
  for (const Case& c : cases) {
    const auto r = test::run_cli(population_command(c.args) + c.args);
    EXPECT_EQ(r.exit_code, c.exit_code) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
  }
}

TEST(PopulationCli, OneSubjectKnownOrNotPrintsItsTables) {
  const auto r = test::run_cli(population_command() + "--men 1 --women 0 --scenarios flexion --frames 20 --known-worker --rules mean");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| subject | sex | stature |"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("test set, spine placement measured, stature and mass given, rules at their means: 1 runs"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("| L5 |"), std::string::npos) << "the per-level bias table\n" << r.output;
}

// Named when it is not the default (one step).
TEST(PopulationCli, TheRefinementIsNamedInThePooledTitle) {
  const auto r = test::run_cli(population_command() + "--men 1 --women 0 --scenarios flexion --frames 20 --refine-steps 0");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("test set, spine placement measured, refine_steps 0: 1 runs"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace spinewatch
