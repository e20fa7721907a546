// spinewatch replay: every frame pair of a recording, as fast as the machine
// allows, to the NDJSON posture stream (interfaces.md §4).
#include <memory>
#include <optional>

#include <spdlog/spdlog.h>

#include "command.hpp"
#include "output_file.hpp"
#include "progress_bar.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/estimator_options.hpp"
#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/replay/overlay.hpp"
#include "spinewatch/replay/replay.hpp"

namespace spinewatch::cli {

void add_replay_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string recording, out, config, calibration, overlay;
    std::uint64_t every = 1;
    bool ignore_background = false;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("replay", "Estimate the posture of every frame pair of a recording");
  cmd->add_option("--recording", opts->recording, "recording directory (interfaces.md §2)")->required();
  cmd->add_option("--out", opts->out, "NDJSON output file, - for standard output")->required();
  cmd->add_option("--config", opts->config, "station configuration (estimator settings); defaults otherwise");
  cmd->add_option("--calibration", opts->calibration, "calibration.yaml instead of the recording's");
  cmd->add_flag("--ignore-background", opts->ignore_background,
                "do not use the recording's background_*.png (learn or bootstrap the background instead)");
  auto* overlay_option = cmd->add_option("--overlay", opts->overlay,
                  "also write DIR/pair_<seq>.png: both views with silhouette outline, CVSM fit and vertebrae");
  cmd->add_option("--every", opts->every, "with --overlay: draw every N-th pair (default 1)")
      ->check(CLI::PositiveNumber)
      ->needs(overlay_option);
  cmd->callback([opts, &exit_code] {
    ReplayOptions options;
    if (!opts->config.empty()) {
      auto config = load_config(opts->config);
      if (!config) return exit_code.fail(config.error());
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
    ProgressBar bar("replay");
    auto stats = replay_recording(
        opts->recording, options,
        [&out](const Posture& p) -> Status {
          (*out)->stream() << encode_posture(p) << '\n';
          return Ok{};
        },
        [&bar](const ReplayProgress& p) { bar.update(p.pairs_done, p.pairs_expected); });
    if (!stats) return exit_code.fail(stats.error());
    if (auto s = (*out)->commit(); !s) return exit_code.fail(s.error());
    spdlog::debug("replay: {} pairs, {} lost; {}", stats->pairs, stats->lost, stats->pairing.summary());
    if (overlay) spdlog::info("replay: {} overlays in {}", overlay->written(), opts->overlay);
  });
}

}  // namespace spinewatch::cli
