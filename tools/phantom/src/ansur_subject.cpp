#include "spinewatch/phantom/ansur_subject.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "spinewatch/estimator/anatomy/spine_spec.hpp"

namespace spinewatch::phantom {
namespace {

double radius(double circumference_mm) { return circumference_mm / (2.0 * M_PI); }

}  // namespace

Result<Subject> subject_from_ansur(const anthropometry::AnsurSubject& row, const SkinToVertebra& rule) {
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

  // The spine from the skin landmarks (docs/anthropometry.md).
  s.t1_height_mm = row.cervicale_height_mm - rule.t1_below_cervicale_mm;
  s.l5_height_mm = row.iliocristale_height_mm - rule.l5_below_iliocristale_mm(row.sex == Sex::Male ? spinewatch::Sex::Male
                                                                                                : spinewatch::Sex::Female);
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

Result<Subject> load_ansur_subject(std::string_view spec, const std::filesystem::path& ansur_dir) {
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
  return subject_from_ansur(*row);
}

std::filesystem::path default_ansur_dir() {
  if (const char* dir = std::getenv("SPINEWATCH_ANSUR_DIR"); dir && *dir) return dir;
  return std::filesystem::path(anthropometry::kAnsurRelativeDir);
}

}  // namespace spinewatch::phantom
