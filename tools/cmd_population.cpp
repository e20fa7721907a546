// spinewatch population: measured adults of ANSUR II (the test set by
// default, never the people the regressions were fitted on) rendered by
// the phantom in each scenario and estimated pair by pair; prints each
// run and the pooled errors with the signed bias per level
// (docs/anthropometry.md, "Population sweep").
#include <memory>
#include <sstream>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "progress_bar.hpp"
#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/population/report.hpp"
#include "spinewatch/population/selection.hpp"
#include "spinewatch/population/sweep.hpp"

namespace spinewatch::cli {
namespace {

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

void add_population_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string ansur = std::string(anthropometry::kAnsurRelativeDir);
    std::string set = "test";
    int men = 20, women = 20;
    std::string scenarios = "flexion,lateral_left,twist,seated_flexion";
    std::string placement = "measured";
    int frames = 0;
    bool known_worker = false;
    bool known_landmarks = false;
    std::string rules = "drawn";
    int refine_steps = EstimatorOptions{}.cvsm.refine_steps;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("population",
                                 "Run measured ANSUR II subjects through phantom and estimator; errors per subject and pooled");
  cmd->add_option("--ansur", opts->ansur, "Directory of the ANSUR II CSV files")->capture_default_str();
  cmd->add_option("--set", opts->set, "Subjects of the test set (never fitted on) or of the training set")
      ->check(CLI::IsMember({"test", "train"}))
      ->capture_default_str();
  cmd->add_option("--men", opts->men, "Men, spread over the 5th–95th stature percentiles")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd->add_option("--women", opts->women, "Women, likewise")->check(CLI::Range(0, 1000))->capture_default_str();
  cmd->add_option("--scenarios", opts->scenarios, "Comma-separated phantom scenarios")->capture_default_str();
  cmd->add_option("--spine-placement", opts->placement, "Estimator's spine placement")
      ->check(CLI::IsMember({"measured", "generic"}))
      ->capture_default_str();
  cmd->add_option("--frames", opts->frames, "Person frames per run (0: each scenario's own)")
      ->check(CLI::Range(0, 100000));
  cmd->add_flag("--known-worker", opts->known_worker,
                "Give the estimator each subject's stature and mass, as for a known worker");
  cmd->add_flag("--known-landmarks", opts->known_landmarks,
                "Give each subject's stature, mass, C7 and iliac-crest heights, as for a worker measured at set-up");
  cmd->add_option("--rules", opts->rules,
                  "Each subject's skin-to-vertebra offsets and spine depth: drawn from the published rules' spread "
                  "(the validation protocol) or at their means (what the estimator assumes)")
      ->check(CLI::IsMember({"drawn", "mean"}))
      ->capture_default_str();
  cmd->add_option("--refine-steps", opts->refine_steps,
                  "The fit's outline refinement, as config [cvsm] refine_steps (0: off)")
      ->check(CLI::Range(0, 4))
      ->capture_default_str();
  cmd->callback([opts, &exit_code] {
    // The options first (exit 2), then the data (exit 1).
    population::SweepOptions sweep;
    sweep.scenarios = split_list(opts->scenarios);
    if (sweep.scenarios.empty()) return exit_code.fail(Error{"--scenarios: no scenario given"}, 2);
    auto all = anthropometry::read_ansur(opts->ansur);
    if (!all) return exit_code.fail(all.error());
    population::SelectionOptions selection;
    selection.set = opts->set == "test" ? anthropometry::Partition::Test : anthropometry::Partition::Train;
    selection.men = opts->men;
    selection.women = opts->women;
    const auto subjects = population::select_subjects(*all, selection);
    if (subjects.empty()) return exit_code.fail(Error{"population: no subject matches the selection"});
    sweep.frames = opts->frames;
    sweep.known_worker = opts->known_worker;
    sweep.known_landmarks = opts->known_landmarks;
    sweep.rules = opts->rules == "mean" ? phantom::RuleDraw::Mean : phantom::RuleDraw::Drawn;
    if (auto mode = parse_spine_placement_mode(opts->placement)) sweep.estimator.subject.spine_placement = *mode;
    sweep.estimator.cvsm.refine_steps = opts->refine_steps;

    std::vector<population::Run> runs;
    const std::uint64_t total = subjects.size() * sweep.scenarios.size();
    {
      ProgressBar progress("population");
      for (const auto& subject : subjects)
        for (const auto& scenario : sweep.scenarios) {
          auto run = population::run_subject(subject, scenario, sweep);
          if (!run) return exit_code.fail(run.error());
          runs.push_back(std::move(run).value());
          progress.update(runs.size(), total);
        }
    }
    fmt::print("{}\n", population::format_runs(runs));
    fmt::print("{}", population::format_pooled(population::pool(runs),
                                              fmt::format("{} set, spine placement {}{}{}{}", opts->set, opts->placement,
                                                          opts->known_landmarks ? ", stature, mass, C7 and iliac crest given"
                                                          : opts->known_worker ? ", stature and mass given" : "",
                                                          opts->rules == "mean" ? ", rules at their means" : "",
                                                          opts->refine_steps != EstimatorOptions{}.cvsm.refine_steps
                                                              ? fmt::format(", refine_steps {}", opts->refine_steps)
                                                              : "")));
  });
}

}  // namespace spinewatch::cli
