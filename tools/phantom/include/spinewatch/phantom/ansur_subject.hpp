#pragma once
// A phantom subject built from one measured adult of ANSUR II
// (docs/anthropometry.md): body sizes from the row, and the spine placed
// from the skin landmarks by published skin-to-vertebra relations.
#include <filesystem>
#include <string_view>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/anatomy/spine_placement.hpp"
#include "spinewatch/frames/result.hpp"
#include "spinewatch/phantom/subject.hpp"

namespace spinewatch::phantom {

// The skin-to-vertebra rule (docs/anthropometry.md gives each offset's
// source and spread) is the estimator's (anatomy/spine_placement.hpp):
// one definition, so a measured subject's truth and the estimator's
// prediction differ only by what the rule does not know (the person).

// The subject of one ANSUR row, standing; its name is "ansur:ID".
Result<Subject> subject_from_ansur(const anthropometry::AnsurSubject& row, const SkinToVertebra& rule = {});

// "ansur:ID" → that row of the release in `ansur_dir`, as a subject;
// an unknown or malformed id is an error naming it.
Result<Subject> load_ansur_subject(std::string_view spec, const std::filesystem::path& ansur_dir);
inline constexpr std::string_view kAnsurSubjectPrefix = "ansur:";

// Where `--subject ansur:ID` looks for the release: $SPINEWATCH_ANSUR_DIR,
// else ../shared/data/ansur2 from the working directory (the repository
// root, with ../shared beside it).
std::filesystem::path default_ansur_dir();

}  // namespace spinewatch::phantom
