// scene_sweep: the scene conditions of docs/phantom.md ("Conditions") ×
// scenarios × subjects through the whole estimator, one line each: pairs,
// how many were tracking / init / lost, the first tracking pair, neck and
// waist mean and the worst tracking error. Not a test (the test,
// scene_conditions_test.cpp, runs a fixed subset); the table in
// docs/tuning.md comes from it:
//   build/release/tests/estimator/cvsm/scene_sweep --seed 3 [--refine-steps 0]
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <spdlog/cfg/env.h>

#include "scene_conditions.hpp"
#include "scene_run.hpp"

int main(int argc, char** argv) {
  using namespace spinewatch;
  CLI::App app{"Scene conditions through the whole estimator"};
  std::vector<std::string> scenarios{"upright", "flexion", "lateral_left", "combined", "seated_flexion", "sway"};
  std::vector<std::string> subjects{"petite", "tall"};
  std::vector<std::string> conditions;
  for (const auto& c : test::scene_conditions()) conditions.emplace_back(c.name);
  unsigned seed = 3;
  int refine_steps = CvsmOptions{}.refine_steps;
  app.add_option("--scenarios", scenarios)->capture_default_str();
  app.add_option("--subjects", subjects)->capture_default_str();
  app.add_option("--conditions", conditions)->capture_default_str();
  app.add_option("--seed", seed)->capture_default_str();
  app.add_option("--refine-steps", refine_steps, "config [cvsm] refine_steps")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  spdlog::cfg::load_env_levels();  // SPDLOG_LEVEL=debug shows the bootstrap's attempts

  std::printf("%-16s %-7s %-14s %5s %5s %5s %5s %6s %6s %7s %7s %7s %8s\n", "scenario", "subject", "condition",
              "pairs", "track", "init", "lost", "no_bg", "first", "neck", "waist", "worst", "updates");
  int failures = 0;
  for (const auto& scenario : scenarios)
    for (const auto& subject : subjects)
      for (const auto& condition : conditions) {
        const test::SceneCondition* c = test::find_scene_condition(condition);
        if (!c) {
          std::fprintf(stderr, "%s: unknown condition\n", condition.c_str());
          return 2;
        }
        auto seq = test::scene_sequence(scenario, subject, seed, *c);
        if (!seq) {
          std::fprintf(stderr, "%s / %s / %s: %s\n", scenario.c_str(), subject.c_str(), condition.c_str(),
                       seq.error().message.c_str());
          ++failures;
          continue;
        }
        test::SceneRunOptions options = test::scene_run_options(*c);
        options.estimator.cvsm.refine_steps = refine_steps;
        const test::SceneRunStats st = test::run_scene(*seq, options);
        std::printf("%-16s %-7s %-14s %5d %5d %5d %5d %6d %6d %7.1f %7.1f %7.1f %8llu\n", scenario.c_str(),
                    subject.c_str(), condition.c_str(), st.pairs, st.tracking, st.init, st.lost, st.no_background,
                    st.first_tracking, test::mean(st.neck), test::mean(st.waist), st.worst,
                    static_cast<unsigned long long>(st.background.updates));
        std::fflush(stdout);
      }
  return failures == 0 ? 0 : 1;
}
