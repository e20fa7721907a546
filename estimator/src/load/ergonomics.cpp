#include "spinewatch/estimator/load/ergonomics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/toml_fields.hpp"
#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/load/schultz.hpp"
#include "spinewatch/estimator/units.hpp"

namespace spinewatch {
namespace {

constexpr std::int64_t kMinuteNs = 60'000'000'000;

}  // namespace

Result<ErgonomicLimits> parse_ergonomic_limits(std::string_view text, std::string_view source) {
  auto root = detail::parse_toml(text, source);
  if (!root) return root.error();
  auto t = detail::toml_table(*root, "limits", source);
  if (!t) return t.error();
  ErgonomicLimits l;
  double per_minute = 2;
  if (auto s = detail::read_numbers(**t, source, "limits",
                                    {{"inclination_ok_deg", &l.inclination_ok_deg, 0, 90},
                                     {"inclination_max_deg", &l.inclination_max_deg, 0, 90},
                                     {"inclination_max_hold_s", &l.inclination_max_hold_s, 0, 86400},
                                     {"extension_margin_deg", &l.extension_margin_deg, 0, 30},
                                     {"bend_twist_deg", &l.bend_twist_deg, 0, 90},
                                     {"bend_twist_hysteresis_deg", &l.bend_twist_hysteresis_deg, 0, 30},
                                     {"bend_twist_per_minute", &per_minute, 1, 1000},
                                     {"niosh_action_limit_n", &l.niosh_action_limit_n, 0, 1e5},
                                     {"niosh_maximum_n", &l.niosh_maximum_n, 0, 1e5},
                                     {"reba_upright_deg", &l.reba_upright_deg, 0, 30},
                                     {"reba_twist_side_deg", &l.reba_twist_side_deg, 0, 90}});
      !s)
    return s.error();
  l.bend_twist_per_minute = int(std::lround(per_minute));
  if (l.inclination_max_deg < l.inclination_ok_deg)
    return Error{fmt::format("{}: limits.inclination_max_deg: below inclination_ok_deg", source)};
  if (l.bend_twist_hysteresis_deg > l.bend_twist_deg)
    return Error{fmt::format("{}: limits.bend_twist_hysteresis_deg: above bend_twist_deg", source)};
  return l;
}

bool within_bend_twist_entry(bool was_in, double value_deg, const ErgonomicLimits& limits) {
  const double magnitude = std::abs(value_deg);
  return magnitude > limits.bend_twist_deg || (was_in && magnitude > limits.bend_twist_deg - limits.bend_twist_hysteresis_deg);
}

const ErgonomicLimits& default_ergonomic_limits() {
  static const ErgonomicLimits limits = [] {
    auto parsed = parse_ergonomic_limits(segments_toml(), "config/segments.toml");
    if (!parsed) throw std::logic_error(parsed.error().message);
    return std::move(parsed).value();
  }();
  return limits;
}

TrunkAngles trunk_angles(const SpinePose& pose, const SpinePose& neutral) {
  const Eigen::Vector3d d = (pose[kNeckIndex].body_center - pose[kWaistIndex].body_center).normalized();
  const Eigen::Vector3d d0 = (neutral[kNeckIndex].body_center - neutral[kWaistIndex].body_center).normalized();
  TrunkAngles a;
  a.inclination_deg = (std::atan2(d.x(), d.y()) - std::atan2(d0.x(), d0.y())) * kDegPerRad;
  a.lateral_deg = (std::asin(std::clamp(d.z(), -1.0, 1.0)) - std::asin(std::clamp(d0.z(), -1.0, 1.0))) * kDegPerRad;
  const Eigen::Quaterniond rel = pose[kWaistIndex].q.conjugate() * pose[kNeckIndex].q;
  const Eigen::Quaterniond rel0 = neutral[kWaistIndex].q.conjugate() * neutral[kNeckIndex].q;
  a.twist_deg = joint_angles(rel * rel0.conjugate()).twist;
  return a;
}

Eigen::Vector3d facing_of(const SpinePose& pose) {
  Eigen::Vector3d anterior = pose[kWaistIndex].q * Eigen::Vector3d::UnitX();
  anterior.y() = 0;
  // L5 tipped past the vertical (never in a posture) would leave no direction; keep +X then.
  return anterior.norm() > 1e-6 ? Eigen::Vector3d(anterior.normalized()) : Eigen::Vector3d::UnitX();
}

TrunkTilt trunk_tilt(const SpinePose& pose, const Eigen::Vector3d& facing) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d right = facing.cross(up);  // +X × +Y = +Z, the subject's right at heading 0
  const Eigen::Vector3d d = (pose[kNeckIndex].body_center - pose[kWaistIndex].body_center).normalized();
  return {std::atan2(d.dot(facing), d.dot(up)) * kDegPerRad, std::asin(std::clamp(d.dot(right), -1.0, 1.0)) * kDegPerRad};
}

int reba_trunk_score(const TrunkAngles& a, const ErgonomicLimits& l) {
  int score;
  if (std::abs(a.inclination_deg) <= l.reba_upright_deg) score = 1;
  else if (a.inclination_deg > 60) score = 4;
  else if (a.inclination_deg > 20 || a.inclination_deg < -20) score = 3;
  else score = 2;
  if (std::abs(a.lateral_deg) > l.reba_twist_side_deg || std::abs(a.twist_deg) > l.reba_twist_side_deg) ++score;
  return score;
}

ErgonomicsMonitor::ErgonomicsMonitor(const SpinePose& neutral, ErgonomicLimits limits)
    : neutral_(neutral), limits_(limits) {}

ErgonomicFlag ErgonomicsMonitor::flag(const std::string& rule, const std::string& state, double value,
                                      std::int64_t t_ns) {
  Held& h = held_[rule];
  if (h.severity != state || t_ns < h.since_ns) h = {state, t_ns};
  return {rule, "", value, double(t_ns - h.since_ns) * 1e-9};
}

std::string ErgonomicsMonitor::bend_twist_severity(const std::string& rule, double value_deg, std::int64_t t_ns) {
  auto& entries = entries_[rule];
  while (!entries.empty() && (t_ns - entries.front() >= kMinuteNs || t_ns < entries.front())) entries.pop_front();
  const bool over = std::abs(value_deg) > limits_.bend_twist_deg;
  bool& in_entry = in_entry_[rule];
  const bool in_now = within_bend_twist_entry(in_entry, value_deg, limits_);
  if (in_now && !in_entry) entries.push_back(t_ns);
  in_entry = in_now;
  if (!over) return "ok";
  return int(entries.size()) >= limits_.bend_twist_per_minute ? "not_acceptable" : "conditional";
}

Ergonomics ErgonomicsMonitor::update(const SpinePose& pose, const std::vector<LevelLoad>& loads, std::int64_t t_ns) {
  const TrunkAngles a = trunk_angles(pose, neutral_);
  Ergonomics e;
  e.trunk_inclination_deg = a.inclination_deg;
  e.lateral_bend_deg = a.lateral_deg;
  e.twist_deg = a.twist_deg;
  e.reba_trunk = reba_trunk_score(a, limits_);

  // ISO 11226 trunk inclination; held_s counts time within the current band.
  const double inc = a.inclination_deg;
  const std::string band = inc < -limits_.extension_margin_deg ? "extension"
                           : inc <= limits_.inclination_ok_deg  ? "ok"
                           : inc <= limits_.inclination_max_deg ? "limited"
                                                                : "over";
  ErgonomicFlag f = flag("iso11226_trunk_inclination", band, inc, t_ns);
  f.severity = band == "ok" ? "ok"
               : band == "limited" && f.held_s <= limits_.inclination_max_hold_s ? "conditional"
                                                                                  : "not_acceptable";
  e.flags.push_back(f);

  for (auto [rule, value] : {std::pair{"iso11226_lateral_bend", a.lateral_deg}, std::pair{"iso11226_axial_twist", a.twist_deg}}) {
    const std::string severity = bend_twist_severity(rule, value, t_ns);
    ErgonomicFlag g = flag(rule, severity, value, t_ns);
    g.severity = severity;
    e.flags.push_back(g);
  }

  // NIOSH 1981: the largest lumbar compression.
  double lumbar = 0;
  for (const LevelLoad& l : loads)
    if (auto i = vertebra_index(l.level); i && *i >= kFirstLumbarIndex) lumbar = std::max(lumbar, l.compression_n);
  if (!loads.empty()) {
    const std::string severity = lumbar >= limits_.niosh_maximum_n        ? "not_acceptable"
                                 : lumbar >= limits_.niosh_action_limit_n ? "conditional"
                                                                          : "ok";
    ErgonomicFlag g = flag("niosh_compression", severity, lumbar, t_ns);
    g.severity = severity;
    e.flags.push_back(g);
  }
  return e;
}

}  // namespace spinewatch
