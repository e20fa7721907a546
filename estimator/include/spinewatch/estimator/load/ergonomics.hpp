#pragma once
// Per-frame ergonomic rules with holding time (ISO 11226 / EN 1005-4,
// NIOSH 1981, REBA trunk score); limits from config/segments.toml.
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct ErgonomicLimits {
  double inclination_ok_deg = 20, inclination_max_deg = 60, inclination_max_hold_s = 60;
  double extension_margin_deg = 2;
  double bend_twist_deg = 10;
  // An entry beyond bend_twist_deg ends only below the limit by this much:
  // an angle held near the limit, estimated a step either side of it from
  // pair to pair, is one entry, not one per step.
  double bend_twist_hysteresis_deg = 2;
  int bend_twist_per_minute = 2;
  double niosh_action_limit_n = 3400, niosh_maximum_n = 6400;
  double reba_upright_deg = 5, reba_twist_side_deg = 5;
};
Result<ErgonomicLimits> parse_ergonomic_limits(std::string_view toml_text, std::string_view source);
// Whether a side bend or twist of `value_deg` is within an entry beyond the
// limit, given whether the previous tracked posture was (`was_in`): beyond
// bend_twist_deg it enters; it leaves at bend_twist_deg − hysteresis.
bool within_bend_twist_entry(bool was_in, double value_deg, const ErgonomicLimits& limits);
const ErgonomicLimits& default_ergonomic_limits();

// Trunk angles of a posture against the subject's neutral posture, degrees:
// inclination = forward tilt of the L5→T1 line from its neutral direction in
// the sagittal plane (+ forward), lateral = its tilt in the frontal plane
// (+ right), twist = axial rotation of T1 relative to L5.
struct TrunkAngles {
  double inclination_deg = 0, lateral_deg = 0, twist_deg = 0;
};
TrunkAngles trunk_angles(const SpinePose& pose, const SpinePose& neutral);

// The L5→T1 line's tilt from the world's vertical, degrees, in the frame
// the subject faces (`facing`: a horizontal unit vector, the subject's
// anterior): inclination forwards (+) in the sagittal plane, side bend to
// the subject's right (+) in the frontal plane. Absolute, not against a
// neutral posture, so truth and estimate are measured alike.
struct TrunkTilt {
  double inclination_deg = 0, side_bend_deg = 0;
};
TrunkTilt trunk_tilt(const SpinePose& pose, const Eigen::Vector3d& facing);
// Where a posture faces: L5's anterior (+X) axis laid into the horizontal plane.
Eigen::Vector3d facing_of(const SpinePose& pose);

int reba_trunk_score(const TrunkAngles& a, const ErgonomicLimits& limits);

class ErgonomicsMonitor {
 public:
  ErgonomicsMonitor(const SpinePose& neutral, ErgonomicLimits limits = default_ergonomic_limits());
  // Flags: iso11226_trunk_inclination, iso11226_lateral_bend,
  // iso11226_axial_twist, niosh_compression (max over L1–L5); held_s is how
  // long the flag's current severity has held.
  Ergonomics update(const SpinePose& pose, const std::vector<LevelLoad>& loads, std::int64_t t_ns);

 private:
  struct Held {
    std::string severity;
    std::int64_t since_ns = 0;
  };
  // A flag whose held_s counts from when `state` began (severity left to the caller).
  ErgonomicFlag flag(const std::string& rule, const std::string& state, double value, std::int64_t t_ns);
  std::string bend_twist_severity(const std::string& rule, double value_deg, std::int64_t t_ns);

  SpinePose neutral_;
  ErgonomicLimits limits_;
  std::map<std::string, Held> held_;
  std::map<std::string, bool> in_entry_;                   // bend/twist within an entry (within_bend_twist_entry)
  std::map<std::string, std::deque<std::int64_t>> entries_;  // times an entry began (within_bend_twist_entry), last minute
};

}  // namespace spinewatch
