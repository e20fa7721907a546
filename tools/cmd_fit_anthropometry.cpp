// spinewatch fit-anthropometry: the regressions that predict the C7 and
// iliac-crest heights from what the silhouettes measure, fitted on ANSUR II
// training subjects and scored on the disjoint test subjects
// (docs/anthropometry.md). Writes config/anthropometry.toml.
#include <memory>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "output_file.hpp"
#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/anthropometry/fit.hpp"

namespace spinewatch::cli {

void add_fit_anthropometry_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string ansur = std::string(anthropometry::kAnsurRelativeDir);
    std::string out;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("fit-anthropometry",
                                 "Fit the C7 / iliac-crest regressions on ANSUR II and report them on train and test sets");
  cmd->add_option("--ansur", opts->ansur, "Directory of the ANSUR II CSV files")->capture_default_str();
  cmd->add_option("--out", opts->out, "TOML file to write (- for standard output)")->required();
  cmd->callback([opts, &exit_code] {
    auto subjects = anthropometry::read_ansur(opts->ansur);
    if (!subjects) return exit_code.fail(subjects.error());
    auto fit = anthropometry::fit_anthropometry(*subjects);
    if (!fit) return exit_code.fail(fit.error());
    if (auto written = write_output(opts->out, anthropometry::to_toml(*fit)); !written)
      return exit_code.fail(written.error());
    // The table goes to standard error when the model goes to standard output.
    std::FILE* table = opts->out == "-" ? stderr : stdout;
    fmt::print(table, "{}", anthropometry::report(*fit));
  });
}

}  // namespace spinewatch::cli
