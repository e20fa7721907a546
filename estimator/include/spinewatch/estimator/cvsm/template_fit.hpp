#pragma once
// Fitting the CVSM template (config/cvsm-generic.toml) to a reference
// subject seen at a known pose: every height fraction, offset and section
// of the template is adjusted so that the model, built at the subject's
// true height and placed on its true spine, covers both silhouettes with
// the fewest exclusive-or pixels. This is how the generic template is made
// from the generic reference subject (docs/cvsm.md, `spinewatch fit-cvsm`);
// other subjects then differ from it only by what the subject model
// measures (height, breadths, depths, head).
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch {

// One frame pair of the reference subject in its neutral pose.
struct TemplateSample {
  BitMask frontal, lateral;
  SubjectPosture posture = SubjectPosture::Standing;
  double height_mm = 1750;
  Eigen::Vector3d l5_center{0, 0, 0};  // true L5 body centre, mm
};

struct TemplateFitOptions {
  int levels = 3;            // step halvings
  int steps_per_move = 6;    // consecutive steps one way before the next parameter
};

struct TemplateFit {
  CvsmSpec spec;
  std::int64_t xor_before = 0, xor_after = 0;  // summed over the samples
  int evaluations = 0;
};

TemplateFit fit_cvsm_template(const CameraRig& rig, const CvsmSpec& start, std::span<const TemplateSample> samples,
                              TemplateFitOptions options = {});

// The template text with every fitted number replaced and everything else
// (comments, order, names) kept: the file stays its own documentation.
std::string rewrite_cvsm_values(std::string_view toml_text, const CvsmSpec& spec);

}  // namespace spinewatch
