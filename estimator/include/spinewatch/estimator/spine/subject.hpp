#pragma once
// A subject's neutral spine (SUBJECT.json, docs/interfaces.md §4):
// {"vertebrae": [{"name": "T1", "body_center": [x,y,z], "q": [w,x,y,z],
//   "height_mm": h, "width_mm": w, "depth_mm": d}, … T1…L5]}
#include <array>
#include <filesystem>
#include <string>
#include <string_view>

#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/estimator/spine/vertebra_geometry.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct SubjectVertebra {
  VertebraPose pose;  // neutral
  BodyDims dims;
};
using SubjectSpine = std::array<SubjectVertebra, kVertebraCount>;

// `source` names the file in error messages ("subject.json: vertebrae[3].q: …").
Result<SubjectSpine> parse_subject_json(std::string_view text, std::string_view source);
Result<SubjectSpine> load_subject_file(const std::filesystem::path& path);
std::string subject_to_json(const SubjectSpine& subject);

// The generic spec's neutral spine for a subject of `height_mm`.
SubjectSpine generic_subject(double height_mm);
// A given neutral pose (the subject model's, its spine placed in the
// measured body) with the spec's vertebra sizes (the generic ones unless
// config [spine] model names a file) scaled to the height.
SubjectSpine subject_of_neutral(const SpinePose& neutral, double height_mm,
                                const SpineSpec& spec = generic_spine_spec());
SpinePose neutral_of(const SubjectSpine& subject);

}  // namespace spinewatch
