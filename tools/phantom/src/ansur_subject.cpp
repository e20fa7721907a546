#include "spinewatch/phantom/ansur_subject.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "spinewatch/anthropometry/split.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"

namespace spinewatch::phantom {
namespace {

double radius(double circumference_mm) { return circumference_mm / (2.0 * M_PI); }

// Standard normal variates from one subject's own stream: SplitMix64 over
// (SubjectId, salt), Box–Muller; portable (no library distribution).
class SubjectNormals {
 public:
  explicit SubjectNormals(int subject_id) : state_(anthropometry::splitmix64(std::uint64_t(subject_id) ^ 0x5d3f1a2bc4e9ULL)) {}
  double next(double cut) {
    const double u1 = uniform(), u2 = uniform();
    const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
    return std::clamp(z, -cut, cut);
  }

 private:
  double uniform() {  // (0, 1]
    state_ = anthropometry::splitmix64(state_);
    return (double(state_ >> 11) + 1.0) * 0x1.0p-53;
  }
  std::uint64_t state_;
};

}  // namespace

RuleDeviation draw_rule_deviation(int subject_id, const SpineDepthRule& depth) {
  SubjectNormals z(subject_id);
  const double cut = depth.truncate_sd();
  RuleDeviation d;
  d.t1_below_cervicale_mm = depth.t1_below_cervicale_sd_mm() * z.next(cut);
  d.l5_below_iliocristale_mm = depth.l5_below_iliocristale_sd_mm() * z.next(cut);
  // One person's back fat is thick or thin at every level: the soft
  // tissue's deviation is shared by both regions, the bone's is not.
  const double tissue = z.next(cut);
  d.thoracic_depth_mm = depth.tissue_sd_mm(SpineRegion::Thoracic) * tissue + depth.bone_sd_mm(SpineRegion::Thoracic) * z.next(cut);
  d.lumbar_depth_mm = depth.tissue_sd_mm(SpineRegion::Lumbar) * tissue + depth.bone_sd_mm(SpineRegion::Lumbar) * z.next(cut);
  return d;
}

Result<Subject> subject_from_ansur(const anthropometry::AnsurSubject& row, RuleDraw draw, const SkinToVertebra& rule,
                                   const SpineDepthRule& depth) {
  using anthropometry::Sex;
  Subject s;
  s.name = fmt::format("{}{}", kAnsurSubjectPrefix, row.id);
  s.height_mm = row.stature_mm;
  s.mass_kg = row.mass_kg;
  s.posture = SubjectPosture::Standing;
  // Elliptical sections from the measured breadths and depths; the hips'
  // depth is the buttocks', their deepest level.
  s.chest = {0.5 * row.chest_breadth_mm, 0.5 * row.chest_depth_mm};
  s.waist = {0.5 * row.waist_breadth_mm, 0.5 * row.waist_depth_mm};
  s.hips = {0.5 * row.hip_breadth_mm, 0.5 * row.buttock_depth_mm};
  // The outer width across the shoulders is over the deltoids.
  s.shoulder_width_mm = row.bideltoid_breadth_mm;
  s.neck_radius_mm = radius(row.neck_circumference_base_mm);
  s.head_half_width_mm = 0.5 * row.head_breadth_mm;
  s.head_half_depth_mm = 0.5 * row.head_length_mm;
  // Shoulder to the middle of the hand (the arm capsule ends at the grip).
  s.arm_length_mm = row.acromion_radiale_length_mm + row.radiale_stylion_length_mm + 0.5 * row.hand_length_mm;
  // Limb radii from circumferences (the flexed biceps and forearm are the
  // ANSUR girths: an arm a few mm thick rather than thin).
  s.upper_arm_radius_mm = radius(row.biceps_circumference_mm);
  s.forearm_radius_mm = radius(row.forearm_circumference_mm);
  s.leg_length_mm = row.crotch_height_mm;
  s.thigh_radius_mm = radius(row.thigh_circumference_mm);
  s.shin_radius_mm = radius(row.calf_circumference_mm);
  // A chair set to the person: the seat at the back of the knee.
  s.seat_height_mm = row.popliteal_height_mm;

  // The spine from the skin landmarks and the depth rule at the row's BMI
  // (docs/anthropometry.md), each drawn from its distribution or at its mean.
  const RuleDeviation dev = draw == RuleDraw::Drawn ? draw_rule_deviation(row.id, depth) : RuleDeviation{};
  s.t1_height_mm = row.cervicale_height_mm - (rule.t1_below_cervicale_mm + dev.t1_below_cervicale_mm);
  s.l5_height_mm = row.iliocristale_height_mm -
                   (rule.l5_below_iliocristale_mm(row.sex == Sex::Male ? spinewatch::Sex::Male : spinewatch::Sex::Female) +
                    dev.l5_below_iliocristale_mm);
  // A drawn L5 stays above the measured hip joints (the subject file's
  // limit is 35 mm; a 2-SD draw put one in 6 068 within 28 mm).
  s.l5_height_mm = std::max(*s.l5_height_mm, row.trochanterion_height_mm + 40);
  const double bmi = row.mass_kg / std::pow(row.stature_mm / 1000.0, 2);
  // Inside the trunk whatever the draw (the subject file's own limit).
  s.spine_depth_thoracic_mm = std::min(depth.mean_mm(SpineRegion::Thoracic, bmi) + dev.thoracic_depth_mm,
                                       2 * s.chest.half_depth_mm - 25);
  s.spine_depth_lumbar_mm = std::min(depth.mean_mm(SpineRegion::Lumbar, bmi) + dev.lumbar_depth_mm,
                                     2 * s.waist.half_depth_mm - 25);
  s.shoulder_height_mm = row.acromial_height_mm;
  s.hip_joint_height_mm = row.trochanterion_height_mm;  // README: about the hip-joint centre
  s.sitting_height_mm = row.sitting_height_mm;

  // The head's top at stature: the body puts the neck's base 30 mm
  // (scaled) above T1 and the head's top 1.75 half-heights above the
  // neck's top. The head keeps the generic proportion (ANSUR has no
  // vertex–chin height); the neck takes what is left, at least 10 mm,
  // else the head gives way.
  const double scale = size_scale(generic_spine_spec(), s.height_mm);
  const double room = s.height_mm - (*s.t1_height_mm + 30 * scale);
  s.head_half_height_mm = 115 * scale;
  s.neck_length_mm = room - 1.75 * s.head_half_height_mm;
  if (s.neck_length_mm < 10) {
    s.neck_length_mm = 10;
    s.head_half_height_mm = (room - 10) / 1.75;
  }
  // Through the subject-file checks, so a row gives only what a file could.
  return parse_subject(to_json(s), s.name);
}

Result<Subject> load_ansur_subject(std::string_view spec, const std::filesystem::path& ansur_dir, RuleDraw draw) {
  if (spec.substr(0, kAnsurSubjectPrefix.size()) != kAnsurSubjectPrefix)
    return Error{fmt::format("{}: not an ANSUR subject (expected {}ID)", spec, kAnsurSubjectPrefix)};
  const std::string_view id_text = spec.substr(kAnsurSubjectPrefix.size());
  int id = 0;
  const auto [ptr, ec] = std::from_chars(id_text.data(), id_text.data() + id_text.size(), id);
  if (id_text.empty() || ec != std::errc() || ptr != id_text.data() + id_text.size() || id <= 0)
    return Error{fmt::format("{}: \"{}\" is not a SubjectId (a positive integer)", spec, id_text)};
  auto subjects = anthropometry::read_ansur(ansur_dir);
  if (!subjects) return subjects.error();
  auto row = anthropometry::find_subject(*subjects, id);
  if (!row) return Error{fmt::format("{}: no subject with SubjectId {} in {}", spec, id, ansur_dir.string())};
  return subject_from_ansur(*row, draw);
}

std::filesystem::path default_ansur_dir() {
  if (const char* dir = std::getenv("SPINEWATCH_ANSUR_DIR"); dir && *dir) return dir;
  return std::filesystem::path(anthropometry::kAnsurRelativeDir);
}

}  // namespace spinewatch::phantom
