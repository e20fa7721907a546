// spinewatch replay: every frame pair of a recording, as fast as the machine
// allows, to the NDJSON posture stream (docs/interfaces.md §4).
#include <memory>
#include <optional>

#include <spdlog/spdlog.h>

#include "command.hpp"
#include "output_file.hpp"
#include "progress_bar.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/estimator_options.hpp"
#include "spinewatch/daemon/exposure_options.hpp"
#include "spinewatch/estimator/load/exposure_json.hpp"
#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/replay/overlay.hpp"
#include "spinewatch/replay/replay.hpp"

namespace spinewatch::cli {

void add_replay_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string recording, out, config, calibration, overlay, summaries;
    std::uint64_t every = 1;
    bool ignore_background = false;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("replay", "Estimate the posture of every frame pair of a recording");
  cmd->add_option("--recording", opts->recording, "recording directory (docs/interfaces.md §2)")->required();
  cmd->add_option("--out", opts->out, "NDJSON output file, - for standard output")->required();
  cmd->add_option("--config", opts->config, "station configuration (estimator settings); defaults otherwise");
  cmd->add_option("--calibration", opts->calibration, "calibration.yaml instead of the recording's");
  cmd->add_flag("--ignore-background", opts->ignore_background,
                "do not use the recording's background_*.png (learn or bootstrap the background instead)");
  cmd->add_option("--summaries", opts->summaries,
                  "also write the exposure summaries (\"class\": \"summary\" lines, docs/exposure.md) to FILE, "
                  "- for standard output; [exposure] interval_s of --config sets their length");
  auto* overlay_option = cmd->add_option("--overlay", opts->overlay,
                  "also write DIR/pair_<seq>.png: both views with silhouette outline, CVSM fit and vertebrae");
  cmd->add_option("--every", opts->every, "with --overlay: draw every N-th pair (default 1)")
      ->check(CLI::PositiveNumber)
      ->needs(overlay_option);
  cmd->callback([opts, &exit_code] {
    ReplayOptions options;
    ExposureOptions exposure;
    if (!opts->config.empty()) {
      auto config = load_config(opts->config);
      if (!config) return exit_code.fail(config.error());
      exposure = exposure_options(*config);
      auto estimator = load_estimator_options(*config);
      if (!estimator) return exit_code.fail(estimator.error());
      options.estimator = std::move(estimator).value();
      options.background_frontal = config->silhouette.background_frontal;
      options.background_lateral = config->silhouette.background_lateral;
    }
    options.calibration = opts->calibration;
    options.ignore_recording_background = opts->ignore_background;
    std::optional<OverlayWriter> overlay;
    if (!opts->overlay.empty()) {
      auto writer = OverlayWriter::create(opts->overlay, opts->every);
      if (!writer) return exit_code.fail(writer.error());
      overlay.emplace(std::move(*writer));
      options.observer = [&overlay](const ReplayedPair& p) { return overlay->write(p); };
    }
    auto out = OutputFile::open(opts->out);
    if (!out) return exit_code.fail(out.error());
    std::unique_ptr<OutputFile> summaries;
    if (!opts->summaries.empty()) {
      if (opts->summaries == "-" && opts->out == "-")
        return exit_code.fail(Error{"--summaries -: --out is standard output already; name a file for one of them"}, 2);
      auto file = OutputFile::open(opts->summaries);
      if (!file) return exit_code.fail(file.error());
      summaries = std::move(file).value();
    }
    ExposureAccumulator accumulator(exposure);
    auto write_summaries = [&summaries](const std::vector<ExposureSummary>& closed) {
      for (const ExposureSummary& s : closed) summaries->stream() << encode_summary(s) << '\n';
    };
    ProgressBar bar("replay");
    auto stats = replay_recording(
        opts->recording, options,
        [&](const Posture& p) -> Status {
          (*out)->stream() << encode_posture(p) << '\n';
          if (summaries) write_summaries(accumulator.add(p));
          return Ok{};
        },
        [&bar](const ReplayProgress& p) { bar.update(p.pairs_done, p.pairs_expected); });
    if (!stats) return exit_code.fail(stats.error());
    if (auto s = (*out)->commit(); !s) return exit_code.fail(s.error());
    if (summaries) {
      write_summaries(accumulator.finish());
      if (auto s = summaries->commit(); !s) return exit_code.fail(s.error());
    }
    spdlog::debug("replay: {} pairs, {} lost; {}", stats->pairs, stats->lost, stats->pairing.summary());
    if (overlay) spdlog::info("replay: {} overlays in {}", overlay->written(), opts->overlay);
  });
}

}  // namespace spinewatch::cli
