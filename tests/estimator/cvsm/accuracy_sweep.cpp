// The CVSM's accuracy over many phantom runs, not one: every noise seed ×
// scenario × subject asked for, one line per run (neck and waist mean 3D
// error, mm, and lost frames), then how many runs have a mean above 10 mm,
// the worst, and the averages. The accuracy test asserts the targets on
// seed 3; a single run moves by ±3 mm with small changes anywhere in the
// estimator (docs/cvsm.md, "How firm these figures are"), so a change is
// judged here, on the whole set. Not run by ctest (≈ 40 s for the
// defaults on one core of the development machine):
//
//   build/release/tests/estimator/cvsm/cvsm_accuracy_sweep --seeds 1-8 [--refine-steps 0]
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "phantom_run.hpp"

int main(int argc, char** argv) {
  using namespace spinewatch;
  CLI::App app{"CVSM neck and waist errors over phantom noise seeds, scenarios and subjects"};
  std::pair<unsigned, unsigned> seeds{1, 8};
  std::vector<std::string> subjects{"petite", "tall"};
  std::vector<std::string> scenarios{"upright", "flexion", "lateral_left", "lateral_right", "twist",
                                     "combined", "seated_flexion", "sway", "fast"};
  int local_budget = CvsmOptions{}.local_budget;
  int refine_steps = CvsmOptions{}.refine_steps;
  int refined_local_budget = CvsmOptions{}.refined_local_budget;
  int refine_row_step = CvsmOptions{}.refine_row_step;
  std::map<std::string, LimbMode> limb_modes{{"fixed", LimbMode::Fixed}, {"articulated", LimbMode::Articulated}};
  LimbMode limbs = CvsmOptions{}.limbs;
  app.add_option("--seeds", seeds, "first and last seed")->delimiter('-');
  app.add_option("--subjects", subjects, "config/subjects/<name>.json")->delimiter(',');
  app.add_option("--scenarios", scenarios, "phantom scenarios")->delimiter(',');
  app.add_option("--local-budget", local_budget, "CvsmOptions::local_budget");
  app.add_option("--refine-steps", refine_steps, "CvsmOptions::refine_steps (config [cvsm] refine_steps)");
  app.add_option("--refined-local-budget", refined_local_budget,
                 "CvsmOptions::refined_local_budget (the local budget when refine_steps > 0)");
  app.add_option("--refine-row-step", refine_row_step, "CvsmOptions::refine_row_step");
  app.add_option("--limbs", limbs, "fixed or articulated (config [cvsm] limbs)")
      ->transform(CLI::CheckedTransformer(limb_modes, CLI::ignore_case));
  CLI11_PARSE(app, argc, argv);
  if (seeds.first > seeds.second) {
    std::fprintf(stderr, "--seeds %u-%u: the first seed is after the last\n", seeds.first, seeds.second);
    return 2;
  }

  CvsmOptions options = test::generic_subject_options();  // the named phantom subjects (phantom_run.hpp)
  options.local_budget = local_budget;
  options.refine_steps = refine_steps;
  options.refined_local_budget = refined_local_budget;
  options.refine_row_step = refine_row_step;
  options.limbs = limbs;
  int runs = 0, neck_over = 0, waist_over = 0;
  double worst = 0, neck_sum = 0, waist_sum = 0;
  for (unsigned seed = seeds.first; seed <= seeds.second; ++seed)
    for (const auto& subject : subjects)
      for (const auto& scenario : scenarios) {
        const auto st = test::run_phantom(scenario, subject, seed, options);
        if (!st.ok()) {
          std::fprintf(stderr, "%s / %s: %s\n", subject.c_str(), scenario.c_str(), st.error().message.c_str());
          return 1;
        }
        const double neck = test::mean(st->neck), waist = test::mean(st->waist);
        std::printf("seed %u %-6s %-14s neck %5.1f waist %5.1f lost %d / %d\n", seed, subject.c_str(), scenario.c_str(),
                    neck, waist, st->lost, st->person_frames);
        ++runs;
        neck_over += neck > 10.0;
        waist_over += waist > 10.0;
        worst = std::max({worst, neck, waist});
        neck_sum += neck;
        waist_sum += waist;
      }
  std::printf("%d runs: neck mean > 10 mm on %d, waist on %d; worst %.1f mm; averages neck %.2f, waist %.2f mm\n", runs,
              neck_over, waist_over, worst, neck_sum / runs, waist_sum / runs);
}
