#pragma once
// A phantom subject built from one measured adult of ANSUR II
// (docs/anthropometry.md): body sizes from the row, and the spine placed
// from the skin landmarks by published skin-to-vertebra relations.
#include <filesystem>
#include <string_view>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/anatomy/spine_depth.hpp"
#include "spinewatch/estimator/anatomy/spine_placement.hpp"
#include "spinewatch/frames/result.hpp"
#include "spinewatch/phantom/subject.hpp"

namespace spinewatch::phantom {

// The skin-to-vertebra rule (docs/anthropometry.md gives each offset's
// source and spread) is the estimator's (anatomy/spine_placement.hpp):
// one definition, so a measured subject's truth and the estimator's
// prediction differ only by what the rule does not know (the person).

// What the rules the row is placed by are taken as. Drawn (the validation
// protocol, docs/anthropometry.md): each subject's skin-to-vertebra
// offsets and spine depth behind the back skin are drawn from the rules'
// published distributions (mean ± SD, clamped at ± truncate_sd), by a
// generator seeded with the SubjectId alone, so a subject is the same
// person in every tool, sweep and test; the estimator uses the means, so
// its figures include the rules' own uncertainty. Mean: every rule at its
// mean (what the estimator assumes; tests of its mechanics use it).
enum class RuleDraw : std::uint8_t { Drawn, Mean };

// The per-subject deviations from the rules' means (mm), as drawn.
struct RuleDeviation {
  double t1_below_cervicale_mm = 0, l5_below_iliocristale_mm = 0;
  double thoracic_depth_mm = 0, lumbar_depth_mm = 0;
};
RuleDeviation draw_rule_deviation(int subject_id, const SpineDepthRule& depth);

// The subject of one ANSUR row, standing; its name is "ansur:ID".
Result<Subject> subject_from_ansur(const anthropometry::AnsurSubject& row, RuleDraw draw = RuleDraw::Drawn,
                                   const SkinToVertebra& rule = {},
                                   const SpineDepthRule& depth = default_spine_depth());

// "ansur:ID" → that row of the release in `ansur_dir`, as a subject;
// an unknown or malformed id is an error naming it.
Result<Subject> load_ansur_subject(std::string_view spec, const std::filesystem::path& ansur_dir,
                                   RuleDraw draw = RuleDraw::Drawn);
inline constexpr std::string_view kAnsurSubjectPrefix = "ansur:";

// Where `--subject ansur:ID` looks for the release: $SPINEWATCH_ANSUR_DIR,
// else ../shared/data/ansur2 from the working directory (the repository
// root, with ../shared beside it).
std::filesystem::path default_ansur_dir();

}  // namespace spinewatch::phantom
