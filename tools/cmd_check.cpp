// spinewatch check: validate a configuration file and a calibration file
// before installing them on a station.
#include <memory>
#include <optional>

#include <fmt/format.h>

#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/estimator_options.hpp"
#include "spinewatch/estimator/calibration/rig_checks.hpp"
#include "spinewatch/estimator/camera_model.hpp"

namespace spinewatch::cli {

void add_check_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string config;
    std::string calibration;
    std::string aspect = "square";
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("check", "Validate a configuration and/or calibration file");
  cmd->add_option("--config", opts->config, "TOML configuration file");
  cmd->add_option("--calibration", opts->calibration, "calibration.yaml (OpenCV FileStorage)");
  cmd->add_option("--aspect", opts->aspect,
                  "square: refuse a camera with fy/fx more than 5 % from 1 (webcams); free: any (anamorphic lenses)")
      ->check(CLI::IsMember({"square", "free"}))
      ->capture_default_str();
  cmd->callback([opts, &exit_code] {
    if (opts->config.empty() && opts->calibration.empty()) {
      spdlog::error("check: give --config and/or --calibration");
      exit_code.value = 2;
      return;
    }
    std::optional<Config> config;
    if (!opts->config.empty()) {
      auto loaded = load_config(opts->config);
      if (!loaded) return exit_code.fail(loaded.error());
      // The model files it names are part of it.
      if (auto models = load_estimator_options(*loaded); !models) return exit_code.fail(models.error());
      spdlog::info("{}: valid", opts->config);
      config = std::move(loaded).value();
    }
    if (!opts->calibration.empty()) {
      auto rig = load_calibration(opts->calibration);
      if (!rig) return exit_code.fail(rig.error());
      // With the configuration, the cameras' resolution must be the calibrated one.
      if (config)
        if (auto s = check_image_size(*rig, config->cameras.width, config->cameras.height); !s)
          return exit_code.fail(Error{fmt::format("{}: {} (cameras.width, cameras.height in {})", opts->calibration,
                                                  s.error().message, opts->config)});
      // The rules calibrate refuses by (docs/calibration.md): a file that
      // breaks them is not a station's, however well-formed.
      RigRules rules;
      rules.free_aspect = opts->aspect == "free";
      const auto problems = rig_problems(*rig, rules);
      for (const auto& p : problems) spdlog::error("{}: {}", opts->calibration, p);
      if (!problems.empty())
        return exit_code.fail(Error{fmt::format("{}: not a usable station calibration ({} problem{}; see above)",
                                                opts->calibration, problems.size(), problems.size() == 1 ? "" : "s")});
      spdlog::info("{}: valid", opts->calibration);
      for (const auto& [name, cam] : {std::pair{"frontal", &rig->frontal}, std::pair{"lateral", &rig->lateral}}) {
        const Eigen::Vector3d c = cam->centre_in_world();
        spdlog::info("  {}: at ({:.0f}, {:.0f}, {:.0f}) mm, f = {:.1f} px, {} distortion coefficients{}", name, c.x(),
                     c.y(), c.z(), cam->camera_matrix(0, 0), cam->distortion().size(),
                     cam->image_width > 0 ? fmt::format(", for {}x{}", cam->image_width, cam->image_height) : "");
      }
    }
  });
}

}  // namespace spinewatch::cli
