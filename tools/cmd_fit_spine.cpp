// spinewatch fit-spine: per-joint bending-stiffness scale factors fitted to
// ground-truth posture streams (the paper's remedy for hand-tuned k and c).
#include <fstream>
#include <memory>

#include <spdlog/spdlog.h>

#include "command.hpp"
#include "output_file.hpp"
#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/estimator/spine/stiffness_fit.hpp"

namespace spinewatch::cli {
namespace {

Result<std::vector<Posture>> read_stream(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{fmt::format("{}: cannot open", path)};
  std::vector<Posture> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    auto p = decode_posture(line, fmt::format("{}:{}", path, n));
    if (!p) return p.error();
    if (p->vertebrae) out.push_back(std::move(p).value());
  }
  if (out.empty()) return Error{fmt::format("{}: no posture lines with vertebrae", path)};
  return out;
}

int run_fit(const std::vector<std::string>& truth, const std::string& subject, double height_mm,
            const std::string& out_path, int rounds, int max_frames) {
  std::vector<std::vector<Posture>> sequences;
  for (const auto& path : truth) {
    auto s = read_stream(path);
    if (!s) {
      spdlog::error("{}", s.error().message);
      return 1;
    }
    sequences.push_back(std::move(s).value());
  }
  auto model = subject.empty() ? Result<SpineModel>(SpineModel::generic(height_mm)) : SpineModel::from_subject_file(subject);
  if (!model) {
    spdlog::error("{}", model.error().message);
    return 1;
  }
  FitOptions fit;
  fit.rounds = rounds;
  fit.max_frames = std::size_t(max_frames);
  const FitResult result = fit_bending_scales(*model, DynamicsOptions{}, sequences, fit);
  spdlog::info("fit-spine: mean vertebra error {:.2f} mm → {:.2f} mm ({} evaluations)", result.initial_error_mm,
               result.final_error_mm, result.evaluations);
  if (auto written = write_output(out_path, stiffness_fragment(result)); !written) {
    spdlog::error("{}", written.error().message);
    return 1;
  }
  return 0;
}

}  // namespace

void add_fit_spine_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::vector<std::string> truth;
    std::string subject, out;
    double height_mm = 1750;
    int rounds = 3, max_frames = 12;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "fit-spine",
      "Fit per-joint bending-stiffness factors to ground-truth sequences (optional: only deform --stiffness "
      "applies them; the shipped stiffness is config/spine-stiffness.toml)");
  cmd->add_option("--truth", opts->truth, "ground-truth posture stream (repeatable)")->required();
  cmd->add_option("--subject", opts->subject, "SUBJECT.json of the sequences' subject (default: generic model)");
  cmd->add_option("--height", opts->height_mm, "height of the generic model, mm")->check(CLI::Range(1000.0, 2300.0));
  cmd->add_option("--rounds", opts->rounds, "coordinate-descent sweeps")->check(CLI::Range(1, 20));
  cmd->add_option("--max-frames", opts->max_frames, "frames used per sequence")->check(CLI::Range(1, 10000));
  cmd->add_option("--out", opts->out, "TOML fragment to write")->required();
  cmd->callback([opts, &exit_code] {
    exit_code.value = run_fit(opts->truth, opts->subject, opts->height_mm, opts->out, opts->rounds, opts->max_frames);
  });
}

}  // namespace spinewatch::cli
