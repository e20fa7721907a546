// spinewatch: the command-line tool of the posture station.
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/daemon/logging.hpp"
#include "spinewatch/version.hpp"

namespace spinewatch::cli {
void ExitCode::fail(const Error& error, int code) {
  spdlog::error("{}", error.message);
  value = code;
}

// `spinewatch --help` lists what a station's user runs first; the commands
// that test the estimator or build its models come after, under their own
// headings. A command not named here is a station command.
void group_commands(CLI::App& app) {
  static const std::map<std::string, std::string> kGroups = {
      {"phantom", "Testing (synthetic subjects with ground truth)"},
      {"eval", "Testing (synthetic subjects with ground truth)"},
      {"deform", "Research and development (docs/spine-model.md, docs/anthropometry.md)"},
      {"fit-spine", "Research and development (docs/spine-model.md, docs/anthropometry.md)"},
      {"fit-cvsm", "Research and development (docs/spine-model.md, docs/anthropometry.md)"},
      {"fit-anthropometry", "Research and development (docs/spine-model.md, docs/anthropometry.md)"},
      {"population", "Research and development (docs/spine-model.md, docs/anthropometry.md)"},
  };
  for (CLI::App* cmd : app.get_subcommands([](CLI::App*) { return true; })) {
    const auto it = kGroups.find(cmd->get_name());
    cmd->group(it != kGroups.end() ? it->second : "Station");
  }
}
}  // namespace spinewatch::cli

int main(int argc, char** argv) {
  using namespace spinewatch;
  CLI::App app{"spinewatch: spine posture from two orthogonal cameras", "spinewatch"};
  app.set_version_flag("--version", kVersion);
  app.require_subcommand(1);
  std::string log_level = "info";
  std::vector<std::string> level_names;
  for (const auto& named : log_level_names()) level_names.push_back(named.first);
  app.add_option("--log-level", log_level, "trace, debug, info, warn or error")->check(CLI::IsMember(level_names));
  // Parsed once, here: the check above let only a level's name through.
  app.parse_complete_callback([&] {
    for (const auto& named : log_level_names())
      if (named.first == log_level) setup_logging(named.second);
  });

  cli::ExitCode exit_code;
  cli::add_check_command(app, exit_code);
  cli::add_background_command(app, exit_code);
  cli::add_replay_command(app, exit_code);
  cli::add_eval_command(app, exit_code);
  cli::add_deform_command(app, exit_code);
  cli::add_fit_spine_command(app, exit_code);
  cli::add_fit_cvsm_command(app, exit_code);
  cli::add_fit_anthropometry_command(app, exit_code);
  cli::add_population_command(app, exit_code);
  cli::add_phantom_command(app, exit_code);
  cli::add_record_command(app, exit_code);
  cli::add_devices_command(app, exit_code);
  cli::add_watch_command(app, exit_code);
  cli::add_report_command(app, exit_code);
  cli::add_calibrate_command(app, exit_code);
  cli::add_export_command(app, exit_code);
  cli::add_import_command(app, exit_code);
  cli::group_commands(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the message and usage hint
    return 2;     // docs/interfaces.md §4: an unknown option or bad value exits 2
  }
  return exit_code.value;
}
