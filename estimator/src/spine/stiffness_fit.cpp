#include "spinewatch/estimator/spine/stiffness_fit.hpp"

#include <cmath>

#include <fmt/format.h>

#include "common/toml_fields.hpp"

namespace spinewatch {

std::optional<SpineTargets> targets_of(const Posture& p) {
  if (!p.vertebrae) return std::nullopt;
  const SpinePose& v = *p.vertebrae;
  SpineTargets t;
  t.neck = p.neck.value_or(v[kNeckIndex].body_center);
  t.waist = p.waist.value_or(v[kWaistIndex].body_center);
  t.neck_dir = p.neck_dir ? *p.neck_dir : Eigen::Vector3d(v[kNeckIndex].q * Eigen::Vector3d::UnitY());
  t.waist_dir = p.waist_dir ? *p.waist_dir : Eigen::Vector3d(v[kWaistIndex].q * Eigen::Vector3d::UnitY());
  return t;
}

double deformation_error(const SpineModel& model, const DynamicsOptions& options,
                         const std::vector<std::vector<Posture>>& sequences, std::size_t max_frames) {
  double sum = 0;
  std::size_t n = 0;
  for (const auto& seq : sequences) {
    // Each sequence deforms continuously from the neutral posture, as the
    // paper's protocol does; frames are subsampled evenly.
    SpineDynamics dynamics(model, options);
    const std::size_t stride = std::max<std::size_t>(1, (seq.size() + max_frames - 1) / std::max<std::size_t>(1, max_frames));
    for (std::size_t f = 0; f < seq.size(); f += stride) {
      auto targets = targets_of(seq[f]);
      if (!targets) continue;
      dynamics.settle(*targets);
      for (std::size_t i = 0; i < kVertebraCount; ++i) {
        sum += (dynamics.pose()[i].body_center - (*seq[f].vertebrae)[i].body_center).norm();
        ++n;
      }
    }
  }
  return n ? sum / double(n) : 0.0;
}

FitResult fit_bending_scales(const SpineModel& model, const DynamicsOptions& options,
                             const std::vector<std::vector<Posture>>& sequences, const FitOptions& fit) {
  FitResult result;
  result.scale = options.bending_scale;
  DynamicsOptions trial = options;
  auto error = [&](const std::array<double, kJointCount>& scale) {
    trial.bending_scale = scale;
    ++result.evaluations;
    return deformation_error(model, trial, sequences, fit.max_frames);
  };
  double best = error(result.scale);
  result.initial_error_mm = best;
  double step = fit.initial_log_step;
  // Coordinate descent on the log of each factor: a joint's stiffness only
  // matters relative to its neighbours', and the log keeps factors positive.
  for (int round = 0; round < fit.rounds; ++round, step *= 0.5) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      for (double direction : {1.0, -1.0}) {
        auto candidate = result.scale;
        candidate[j] *= std::exp(direction * step);
        const double e = error(candidate);
        if (e < best) {
          best = e;
          result.scale = candidate;
          break;
        }
      }
    }
  }
  result.final_error_mm = best;
  return result;
}

std::string stiffness_fragment(const FitResult& r) {
  std::string out = fmt::format(
      "# Per-joint bending-stiffness scale factors fitted by `spinewatch fit-spine`\n"
      "# (mean vertebra error {:.2f} mm before, {:.2f} mm after, {} evaluations).\n"
      "[spine.bending_scale]\n",
      r.initial_error_mm, r.final_error_mm, r.evaluations);
  for (std::size_t j = 0; j < kJointCount; ++j)
    out += fmt::format("\"{}-{}\" = {:.4f}\n", kVertebraNames[j], kVertebraNames[j + 1], r.scale[j]);
  return out;
}

Result<std::array<double, kJointCount>> parse_stiffness_fragment(std::string_view text, std::string_view source) {
  auto root = detail::parse_toml(text, source);
  if (!root) return root.error();
  auto table = detail::toml_table(*root, "spine.bending_scale", source);
  if (!table) return table.error();
  std::array<double, kJointCount> scale = DynamicsOptions::filled_ones();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::string key = fmt::format("{}-{}", kVertebraNames[j], kVertebraNames[j + 1]);
    if (!(*table)->contains(key)) continue;  // unlisted joints keep 1
    auto v = detail::toml_number(**table, key, source, "spine.bending_scale", 0.01, 100);
    if (!v) return v.error();
    scale[j] = *v;
  }
  for (auto&& [key, node] : **table) {
    bool known = false;
    for (std::size_t j = 0; j < kJointCount; ++j)
      known |= key.str() == fmt::format("{}-{}", kVertebraNames[j], kVertebraNames[j + 1]);
    if (!known)
      return Error{fmt::format("{}:{}: spine.bending_scale.{}: unknown joint", source, node.source().begin.line, key.str())};
  }
  return scale;
}

}  // namespace spinewatch
