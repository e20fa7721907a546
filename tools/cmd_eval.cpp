// spinewatch eval: errors of the estimate against a recording's ground truth
// (DIR/ground_truth.ndjson, as the phantom writes it).
#include <filesystem>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "progress_bar.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/estimator_options.hpp"
#include "spinewatch/estimator/spine/deform_report.hpp"
#include "spinewatch/replay/evaluation.hpp"
#include "spinewatch/replay/posture_file.hpp"
#include "spinewatch/replay/replay.hpp"

namespace spinewatch::cli {
namespace {

nlohmann::json stats_json(const ErrorStats& s) { return {{"mean", s.mean}, {"p95", s.p95}, {"max", s.max}, {"n", s.count}}; }

nlohmann::json angle_json(const TrunkAngleScore& a) {
  nlohmann::json j = stats_json(a.error);
  j["bent_frames"] = a.bent_frames;
  j["wrong_side"] = a.wrong_side;
  return j;
}

nlohmann::json evaluation_json(const Evaluation& e) {
  nlohmann::json levels = nlohmann::json::object();
  for (std::size_t i = 0; i < kVertebraCount; ++i) levels[std::string(kVertebraNames[i])] = stats_json(e.per_level[i]);
  return {{"truth_frames", e.truth_frames}, {"estimated_frames", e.estimated_frames},
          {"lost_frames", e.lost_frames},   {"init_frames", e.init_frames},
          {"lost_seqs", e.lost_seqs},       {"neck", stats_json(e.neck)},
          {"waist", stats_json(e.waist)},   {"vertebrae", stats_json(e.all_vertebrae)},
          {"twist_deg", stats_json(e.twist)},               {"twisted_frames", e.twisted_frames},
          {"twisted_published_untwisted", e.twisted_published_untwisted},
          {"twist_unresolved_frames", e.twist_unresolved_frames},
          {"inclination_deg", angle_json(e.inclination)},  {"side_bend_deg", angle_json(e.side_bend)},
          {"per_level", levels}};
}

}  // namespace

void add_eval_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string recording, estimate, truth, config;
    bool json = false;
    bool deform = false;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("eval", "Errors of the estimate against ground truth");
  cmd->add_option("--recording", opts->recording, "recording directory with ground_truth.ndjson");
  cmd->add_option("--estimate", opts->estimate, "posture stream to evaluate; default: replay the recording now");
  cmd->add_option("--truth", opts->truth, "ground truth instead of DIR/ground_truth.ndjson");
  cmd->add_option("--config", opts->config, "station configuration (estimator settings) for the replay");
  cmd->add_flag("--json", opts->json, "print the summary as one JSON object");
  cmd->add_flag("--deform", opts->deform,
                "Table-1 report (per level Δ lateral, vertical, anterior, distance) of `spinewatch deform` output "
                "given with --estimate");
  cmd->callback([opts, &exit_code] {
    auto fail = [&exit_code](const Error& e) { exit_code.fail(e); };
    if (opts->recording.empty() && opts->truth.empty()) {
      spdlog::error("eval: give --recording DIR or --truth FILE");
      exit_code.value = 2;
      return;
    }
    if (opts->deform && opts->estimate.empty()) {
      spdlog::error("eval --deform: give --estimate FILE, the output of spinewatch deform");
      exit_code.value = 2;
      return;
    }
    const std::string truth_path = opts->truth.empty() ? opts->recording + "/ground_truth.ndjson" : opts->truth;
    if (opts->truth.empty() && !std::filesystem::exists(truth_path)) {
      spdlog::error("eval: {} has no ground_truth.ndjson: it is not a phantom recording (only spinewatch phantom "
                    "writes ground truth); give the truth with --truth FILE (docs/phantom.md)",
                    opts->recording);
      exit_code.value = 1;
      return;
    }
    auto truth = read_posture_file(truth_path);
    if (!truth) return fail(truth.error());

    std::vector<Posture> estimate;
    if (!opts->estimate.empty()) {
      auto read = read_posture_file(opts->estimate);
      if (!read) return fail(read.error());
      estimate = std::move(read).value();
    } else {
      ReplayOptions options;
      if (!opts->config.empty()) {
        auto config = load_config(opts->config);
        if (!config) return fail(config.error());
        auto estimator = load_estimator_options(*config);
        if (!estimator) return fail(estimator.error());
        options.estimator = std::move(estimator).value();
      }
      ProgressBar bar("eval");
      auto stats = replay_recording(
          opts->recording, options,
          [&estimate](const Posture& p) -> Status {
            estimate.push_back(p);
            return Ok{};
          },
          [&bar](const ReplayProgress& p) { bar.update(p.pairs_done, p.pairs_expected); });
      if (!stats) return fail(stats.error());
    }
    if (opts->deform) {
      std::cout << format_table(compare_deformation(estimate, *truth));
      return;
    }
    const Evaluation e = evaluate(estimate, *truth);
    if (opts->json)
      std::cout << evaluation_json(e).dump() << '\n';
    else
      std::cout << format_evaluation(e);
  });
}

}  // namespace spinewatch::cli
