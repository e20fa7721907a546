// spinewatch deform: the paper's Table 1 protocol — the accurate model of a
// subject, from its neutral spine, driven to the neck and waist of each
// target line (interfaces.md §4).
#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/load/ergonomics.hpp"
#include "spinewatch/estimator/load/schultz.hpp"
#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/estimator/spine/spine_dynamics.hpp"
#include "spinewatch/estimator/spine/stiffness_fit.hpp"

namespace spinewatch::cli {
namespace {

using nlohmann::json;

Result<Eigen::Vector3d> vec3(const json& line, const char* key, const std::string& where, bool unit) {
  auto it = line.find(key);
  if (it == line.end()) return Error{fmt::format("{}: {}: missing", where, key)};
  if (!it->is_array() || it->size() != 3) return Error{fmt::format("{}: {}: expected an array of 3 numbers", where, key)};
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!(*it)[i].is_number()) return Error{fmt::format("{}: {}[{}]: not a number", where, key, i)};
    v[int(i)] = (*it)[i].get<double>();
  }
  if (!v.allFinite()) return Error{fmt::format("{}: {}: not finite", where, key)};
  if (unit && std::abs(v.norm() - 1.0) > 0.05)
    return Error{fmt::format("{}: {}: not a unit vector (norm {:.3f})", where, key, v.norm())};
  return unit ? Eigen::Vector3d(v.normalized()) : v;
}

struct TargetLine {
  SpineTargets targets;
  std::uint64_t seq = 0;
  std::int64_t t_ns = 0;
};

Result<TargetLine> parse_target(const std::string& text, const std::string& where, std::uint64_t index) {
  json line = json::parse(text, nullptr, false);
  if (line.is_discarded()) return Error{fmt::format("{}: not valid JSON", where)};
  if (!line.is_object()) return Error{fmt::format("{}: expected a JSON object", where)};
  TargetLine t;
  auto neck = vec3(line, "neck", where, false);
  if (!neck) return neck.error();
  auto waist = vec3(line, "waist", where, false);
  if (!waist) return waist.error();
  t.targets.neck = *neck;
  t.targets.waist = *waist;
  for (auto [key, out] : {std::pair{"neck_dir", &t.targets.neck_dir}, std::pair{"waist_dir", &t.targets.waist_dir}}) {
    if (!line.contains(key) || line[key].is_null()) continue;
    auto d = vec3(line, key, where, true);
    if (!d) return d.error();
    *out = *d;
  }
  t.seq = index;
  if (auto it = line.find("seq"); it != line.end()) {
    if (!it->is_number_unsigned()) return Error{fmt::format("{}: seq: not a non-negative integer", where)};
    t.seq = it->get<std::uint64_t>();
  }
  if (auto it = line.find("t_ns"); it != line.end()) {
    if (!it->is_number_integer()) return Error{fmt::format("{}: t_ns: not an integer", where)};
    t.t_ns = it->get<std::int64_t>();
  }
  return t;
}

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
    std::ifstream in(stiffness_path);
    std::stringstream text;
    text << in.rdbuf();
    auto scale = in ? parse_stiffness_fragment(text.str(), stiffness_path)
                    : Result<std::array<double, kJointCount>>(Error{fmt::format("{}: cannot open", stiffness_path)});
    if (!scale) {
      spdlog::error("{}", scale.error().message);
      return 1;
    }
    options.bending_scale = *scale;
  }
  // Read every line first: a bad line fails the run before any output.
  std::ifstream in(targets_path);
  if (!in) {
    spdlog::error("{}: cannot open", targets_path);
    return 1;
  }
  std::vector<TargetLine> lines;
  std::string text;
  for (std::uint64_t n = 1; std::getline(in, text); ++n) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    auto t = parse_target(text, fmt::format("{}:{}", targets_path, n), lines.size());
    if (!t) {
      spdlog::error("{}", t.error().message);
      return 1;
    }
    lines.push_back(*t);
  }
  if (lines.empty()) {
    spdlog::error("{}: no target lines", targets_path);
    return 1;
  }

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
