// spinewatch check: validate a configuration file and a calibration file
// before installing them on a station.
#include <memory>

#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/estimator_options.hpp"
#include "spinewatch/estimator/camera_model.hpp"

namespace spinewatch::cli {

void add_check_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string config;
    std::string calibration;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("check", "Validate a configuration and/or calibration file");
  cmd->add_option("--config", opts->config, "TOML configuration file");
  cmd->add_option("--calibration", opts->calibration, "calibration.yaml (OpenCV FileStorage)");
  cmd->callback([opts, &exit_code] {
    if (opts->config.empty() && opts->calibration.empty()) {
      spdlog::error("check: give --config and/or --calibration");
      exit_code.value = 2;
      return;
    }
    if (!opts->config.empty()) {
      auto config = load_config(opts->config);
      if (!config) return exit_code.fail(config.error());
      // The model files it names are part of it.
      if (auto models = load_estimator_options(*config); !models) return exit_code.fail(models.error());
      spdlog::info("{}: valid", opts->config);
    }
    if (!opts->calibration.empty()) {
      auto rig = load_calibration(opts->calibration);
      if (!rig) return exit_code.fail(rig.error());
      spdlog::info("{}: valid", opts->calibration);
    }
  });
}

}  // namespace spinewatch::cli
