#pragma once
// Each subcommand of the spinewatch CLI lives in its own file and adds
// itself to the app; its callback stores the exit code here.
#include <CLI/CLI.hpp>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::cli {

struct ExitCode {
  int value = 0;

  // Logs the error once and sets the exit code (1: bad input or a failed
  // operation; 2 is for usage errors, docs/interfaces.md §4).
  void fail(const Error& error, int code = 1);
};

void add_check_command(CLI::App& app, ExitCode& exit_code);
void add_background_command(CLI::App& app, ExitCode& exit_code);
void add_replay_command(CLI::App& app, ExitCode& exit_code);
void add_eval_command(CLI::App& app, ExitCode& exit_code);
void add_deform_command(CLI::App& app, ExitCode& exit_code);
void add_fit_spine_command(CLI::App& app, ExitCode& exit_code);
void add_fit_cvsm_command(CLI::App& app, ExitCode& exit_code);
void add_fit_anthropometry_command(CLI::App& app, ExitCode& exit_code);
void add_population_command(CLI::App& app, ExitCode& exit_code);
void add_phantom_command(CLI::App& app, ExitCode& exit_code);
void add_record_command(CLI::App& app, ExitCode& exit_code);
void add_devices_command(CLI::App& app, ExitCode& exit_code);
void add_watch_command(CLI::App& app, ExitCode& exit_code);
void add_report_command(CLI::App& app, ExitCode& exit_code);
void add_calibrate_command(CLI::App& app, ExitCode& exit_code);
void add_export_command(CLI::App& app, ExitCode& exit_code);
void add_import_command(CLI::App& app, ExitCode& exit_code);

}  // namespace spinewatch::cli
