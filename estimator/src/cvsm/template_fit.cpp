#include "spinewatch/estimator/cvsm/template_fit.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "cvsm/xor_cost.hpp"

namespace spinewatch {
namespace {

// A template number the fit may move: where it lives, its step and the
// range the parser accepts.
struct Knob {
  double* value;
  double step, min, max;
};

std::vector<Knob> knobs_of(CvsmSpec& spec) {
  std::vector<Knob> k;
  for (auto& t : spec.trunk) {
    k.push_back({&t.half_width, 0.003, 0.01, 0.3});
    k.push_back({&t.depth, 0.004, 0.01, 0.3});
    k.push_back({&t.spine_fraction, 0.02, 0.05, 0.95});
  }
  for (auto& p : spec.parts) {
    k.push_back({&p.y, 0.004, 0.0, 1.1});
    k.push_back({&p.x, 0.004, -0.3, 0.3});
    k.push_back({&p.z, 0.004, -0.3, 0.3});
    k.push_back({&p.half_width, 0.003, 0.001, 0.3});
    k.push_back({&p.front, 0.003, 0.001, 0.3});
    k.push_back({&p.back, 0.003, 0.001, 0.3});
  }
  k.push_back({&spec.hip_y, 0.004, 0.3, 0.7});
  k.push_back({&spec.hip_x, 0.004, -0.2, 0.2});
  k.push_back({&spec.hip_z, 0.004, 0.0, 0.2});
  k.push_back({&spec.thigh, 0.006, 0.1, 0.4});
  return k;
}

class SampleCost {
 public:
  SampleCost(const CameraRig& rig, std::span<const TemplateSample> samples)
      : samples_(samples),
        cost_(rig, samples.empty() ? 1 : samples.front().frontal.width(), samples.empty() ? 1 : samples.front().frontal.height()) {}

  std::int64_t operator()(const CvsmSpec& spec) {
    std::int64_t total = 0;
    for (const TemplateSample& s : samples_) {
      BodyShape shape;
      shape.height_mm = s.height_mm;
      shape.posture = s.posture;
      const BodyModel model = build_body_model(spec, spine_, shape, s.l5_center);
      control_points(model, pose_vertebrae(model, spine_, CvsmPose{}), points_);
      cost_.set_silhouettes(s.frontal, s.lateral);
      total += cost_.evaluate(model, points_).total();
    }
    return total;
  }

 private:
  std::span<const TemplateSample> samples_;
  const SpineSpec& spine_ = generic_spine_spec();
  XorCost cost_;
  std::vector<Eigen::Vector3d> points_;
};

// Rounded as the file prints them, so the fit is judged on what is written.
double printed(double v) { return std::round(v * 1000.0) / 1000.0; }

}  // namespace

TemplateFit fit_cvsm_template(const CameraRig& rig, const CvsmSpec& start, std::span<const TemplateSample> samples,
                              TemplateFitOptions options) {
  TemplateFit fit{start, 0, 0, 0};
  SampleCost cost(rig, samples);
  std::vector<Knob> knobs = knobs_of(fit.spec);
  for (Knob& k : knobs) *k.value = printed(*k.value);
  fit.xor_before = fit.xor_after = cost(fit.spec);
  ++fit.evaluations;
  // Coordinate descent, coarse to fine: a sample set of a few frame pairs
  // costs well under a millisecond per evaluation, so a plain sweep over a
  // hundred-odd numbers is quick and every move is easy to follow.
  for (int level = 0; level < options.levels; ++level) {
    const double scale = std::ldexp(1.0, -level);
    for (Knob& k : knobs) {
      for (double dir : {1.0, -1.0}) {
        bool improved = false;
        for (int n = 0; n < options.steps_per_move; ++n) {
          const double old = *k.value;
          const double next = printed(std::clamp(old + dir * k.step * scale, k.min, k.max));
          if (next == old) break;
          *k.value = next;
          const std::int64_t c = cost(fit.spec);
          ++fit.evaluations;
          if (c >= fit.xor_after) {
            *k.value = old;
            break;
          }
          fit.xor_after = c;
          improved = true;
        }
        if (improved) break;
      }
    }
  }
  return fit;
}

std::string rewrite_cvsm_values(std::string_view toml_text, const CvsmSpec& spec) {
  // Section by section, in file order, the numbers the parser reads.
  std::vector<std::map<std::string, double>> trunk, parts;
  for (const auto& t : spec.trunk) trunk.push_back({{"half_width", t.half_width}, {"depth", t.depth}, {"spine_fraction", t.spine_fraction}});
  for (const auto& p : spec.parts)
    parts.push_back({{"y", p.y}, {"x", p.x}, {"z", p.z}, {"half_width", p.half_width}, {"front", p.front}, {"back", p.back}});
  const std::map<std::string, double> hip{{"y", spec.hip_y}, {"x", spec.hip_x}, {"z", spec.hip_z}, {"thigh", spec.thigh}};

  std::ostringstream out;
  std::istringstream in{std::string(toml_text)};
  const std::map<std::string, double>* section = nullptr;
  std::size_t trunk_n = 0, part_n = 0;
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    if (!first) out << '\n';
    first = false;
    if (line.rfind("[[trunk]]", 0) == 0) {
      section = trunk_n < trunk.size() ? &trunk[trunk_n++] : nullptr;
    } else if (line.rfind("[[part]]", 0) == 0) {
      section = part_n < parts.size() ? &parts[part_n++] : nullptr;
    } else if (line.rfind("[hip]", 0) == 0) {
      section = &hip;
    } else if (line.rfind('[', 0) == 0) {
      section = nullptr;
    } else if (section) {
      const auto eq = line.find('=');
      const auto key_end = line.find_first_of(" \t=");
      if (eq != std::string::npos && key_end != std::string::npos) {
        const auto it = section->find(line.substr(0, key_end));
        if (it != section->end()) {
          const auto value_begin = line.find_first_not_of(" \t", eq + 1);
          const auto value_end = line.find_first_of(" \t#", value_begin);
          const std::string value = fmt::format("{:.3f}", it->second);
          std::string rest = value_end == std::string::npos ? "" : line.substr(value_end);
          // Keep trailing comments where they were when the number's width changes.
          const auto old_width = (value_end == std::string::npos ? line.size() : value_end) - value_begin;
          if (!rest.empty() && value.size() != old_width && rest.find_first_not_of(' ') != std::string::npos) {
            const auto pad = rest.find_first_not_of(' ');
            const long spaces = static_cast<long>(pad) + static_cast<long>(old_width) - static_cast<long>(value.size());
            rest = std::string(static_cast<std::size_t>(std::max(1L, spaces)), ' ') + rest.substr(pad);
          }
          line = line.substr(0, value_begin) + value + rest;
        }
      }
    }
    out << line;
  }
  if (!toml_text.empty() && toml_text.back() == '\n') out << '\n';
  return out.str();
}

}  // namespace spinewatch
