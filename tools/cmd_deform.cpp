// spinewatch deform: the paper's Table 1 protocol — the accurate model of a
// subject, from its neutral spine, driven to the neck and waist of each
// target line (docs/interfaces.md §4).
#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/load/ergonomics.hpp"
#include "spinewatch/estimator/load/schultz.hpp"
#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/estimator/spine/spine_dynamics.hpp"
#include "spinewatch/estimator/spine/stiffness_fit.hpp"
#include "spinewatch/estimator/spine/target_lines.hpp"
#include "spinewatch/frames/text_file.hpp"

namespace spinewatch::cli {
namespace {

int run_deform(const std::string& subject_path, const std::string& targets_path, const std::string& out_path,
               const std::string& stiffness_path) {
  // Everything is read and checked before the (slower) model is built.
  auto subject = load_subject_file(subject_path);
  if (!subject) {
    spdlog::error("{}", subject.error().message);
    return 1;
  }
  DynamicsOptions options;
  if (!stiffness_path.empty()) {
    auto text = read_text_file(stiffness_path);
    auto scale = text ? parse_stiffness_fragment(*text, stiffness_path)
                      : Result<std::array<double, kJointCount>>(text.error());
    if (!scale) {
      spdlog::error("{}", scale.error().message);
      return 1;
    }
    options.bending_scale = *scale;
  }
  // Read every line first: a bad line fails the run before any output.
  auto targets_text = read_text_file(targets_path);
  if (!targets_text) {
    spdlog::error("{}", targets_text.error().message);
    return 1;
  }
  auto targets = parse_target_lines(*targets_text, targets_path);
  if (!targets) {
    spdlog::error("{}", targets.error().message);
    return 1;
  }
  const std::vector<TargetLine>& lines = *targets;

  const SpineModel model = SpineModel::from_subject(*subject);
  std::ofstream file;
  if (out_path != "-") {
    file.open(out_path, std::ios::trunc);
    if (!file) {
      spdlog::error("{}: cannot write", out_path);
      return 1;
    }
  }
  std::ostream& out = out_path == "-" ? std::cout : file;
  SpineDynamics dynamics(model, options);
  ErgonomicsMonitor ergonomics(model.neutral());
  const LoadParams& load_params = default_load_params();
  std::size_t unconverged = 0;
  for (const TargetLine& line : lines) {
    const auto start = std::chrono::steady_clock::now();
    const SettleReport report = dynamics.settle(line.targets);
    if (!report.converged) ++unconverged;
    Posture p;
    p.seq = line.seq;
    p.t_ns = line.t_ns;
    p.state = TrackingState::Tracking;
    p.vertebrae = dynamics.pose();
    p.neck = dynamics.pose()[kNeckIndex].body_center;
    p.waist = dynamics.pose()[kWaistIndex].body_center;
    p.neck_dir = dynamics.pose()[kNeckIndex].q * Eigen::Vector3d::UnitY();
    p.waist_dir = dynamics.pose()[kWaistIndex].q * Eigen::Vector3d::UnitY();
    p.fit.cost = 0;
    const auto angles = intervertebral_angles(dynamics.pose());
    for (std::size_t j = 0; j < kJointCount; ++j)
      p.angles.push_back({fmt::format("{}-{}", kVertebraNames[j], kVertebraNames[j + 1]), angles[j].flexion,
                          angles[j].lateral, angles[j].twist});
    p.loads = compute_loads(dynamics.pose(), load_params);
    p.ergonomics = ergonomics.update(dynamics.pose(), p.loads, p.t_ns);
    p.latency_us = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - start).count();
    out << encode_posture(p) << '\n';
  }
  out.flush();
  if (!out) {
    spdlog::error("{}: write failed", out_path);
    return 1;
  }
  if (unconverged)
    spdlog::warn("deform: {} of {} lines stopped at the iteration cap before Eqs. 19–20 held", unconverged, lines.size());
  return 0;
}

}  // namespace

void add_deform_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string subject, targets, out, stiffness;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("deform", "Drive a subject's accurate spine model to neck/waist targets (Table 1 protocol)");
  cmd->add_option("--subject", opts->subject, "SUBJECT.json: the subject's neutral spine")->required();
  cmd->add_option("--targets", opts->targets, "TARGETS.ndjson: neck, waist (and neck_dir, waist_dir) per line")->required();
  cmd->add_option("--out", opts->out, "posture stream NDJSON, - for standard output")->required();
  cmd->add_option("--stiffness", opts->stiffness, "bending-scale fragment written by fit-spine");
  cmd->callback([opts, &exit_code] { exit_code.value = run_deform(opts->subject, opts->targets, opts->out, opts->stiffness); });
}

}  // namespace spinewatch::cli
