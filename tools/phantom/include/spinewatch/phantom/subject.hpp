#pragma once
// The synthetic subject's body measurements (config/subjects/*.json,
// docs/phantom.md). All lengths in millimetres.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::phantom {

enum class SubjectPosture : std::uint8_t { Standing, Seated };
std::string_view to_string(SubjectPosture posture);

// An elliptical trunk cross-section: half the width (left–right) and half
// the depth (front–back).
struct Section {
  double half_width_mm = 0;
  double half_depth_mm = 0;
};

struct Subject {
  std::string name = "generic";
  double height_mm = 1750;
  double mass_kg = 75;
  SubjectPosture posture = SubjectPosture::Standing;
  Section chest{150, 105}, waist{130, 95}, hips{165, 105};
  double shoulder_width_mm = 400;
  double neck_radius_mm = 55, neck_length_mm = 95;
  double head_half_width_mm = 75, head_half_depth_mm = 95, head_half_height_mm = 115;
  double arm_length_mm = 750, upper_arm_radius_mm = 45, forearm_radius_mm = 35;
  double leg_length_mm = 900, thigh_radius_mm = 85, shin_radius_mm = 55;
  // Body-centre distance in front of the back skin surface.
  double spine_depth_thoracic_mm = 60, spine_depth_lumbar_mm = 70;
  double seat_height_mm = 460;
  // A measured person's landmarks (docs/anthropometry.md), each optional;
  // absent, the generic proportions scaled by height_mm place them.
  // Standing heights above the floor of T1's and L5's body centres: the
  // spine between follows the generic curve, sized to span them.
  std::optional<double> t1_height_mm, l5_height_mm;
  std::optional<double> shoulder_height_mm;   // acromion, standing
  std::optional<double> hip_joint_height_mm;  // hip-joint centres, standing
  std::optional<double> sitting_height_mm;    // top of the head above the seat, sitting erect
  // Multipliers on each joint's share of a whole-spine bend (renormalised);
  // absent: drawn from the recording's seed, ±20 %.
  std::optional<std::array<JointAngles, kJointCount>> joint_factors;
};

// `source` names the file in messages: "petite.json: trunk.waist.half_width_mm: missing".
Result<Subject> parse_subject(const nlohmann::json& j, std::string_view source);
Result<Subject> load_subject(const std::filesystem::path& path);
// The same format parse_subject reads (recording.json "subject").
nlohmann::json to_json(const Subject& subject);

}  // namespace spinewatch::phantom
