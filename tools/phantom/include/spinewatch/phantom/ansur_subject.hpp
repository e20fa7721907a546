#pragma once
// A phantom subject built from one measured adult of ANSUR II
// (docs/anthropometry.md): body sizes from the row, and the spine placed
// from the skin landmarks by published skin-to-vertebra relations.
#include <filesystem>
#include <string_view>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/frames/result.hpp"
#include "spinewatch/phantom/subject.hpp"

namespace spinewatch::phantom {

// Vertical offsets from a skin landmark down to a vertebral body centre,
// standing, mm (docs/anthropometry.md gives each one's source and spread).
struct SkinToVertebra {
  // T1 body centre below the C7 spinous process tip (cervicale): the tip
  // of the long, caudally sloping C7 process lies at about the level of
  // the C7/T1 disc, T1's centre a little below it.
  double t1_below_cervicale_mm = 15;
  // L5 body centre below the iliac-crest height (iliocristale): the
  // intercristal (Tuffier's) line crosses mostly the lower L4 body in men
  // and the upper L5 body in women (Snider et al. 2008), at L4/L5 pooled
  // (Kim et al. 2003).
  double l5_below_iliocristale_male_mm = 25;
  double l5_below_iliocristale_female_mm = 10;
};

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
