// The template fit (spinewatch fit-cvsm) and the template rewriter.
#include <algorithm>
#include <string>

#include <gtest/gtest.h>

#include "cvsm/xor_cost.hpp"
#include "spinewatch/estimator/cvsm/template_fit.hpp"

namespace spinewatch {
namespace {

// Masks of `spec`'s own model at the neutral pose: a subject the template
// describes exactly, so the fit knows where to go back to.
TemplateSample sample_of(const CvsmSpec& spec, SubjectPosture posture) {
  const CameraRig rig = CameraRig::default_rig();
  const SpineSpec& spine = generic_spine_spec();
  TemplateSample s;
  s.posture = posture;
  s.height_mm = 1750;
  s.l5_center = {0, posture == SubjectPosture::Standing ? spine.l5_height_fraction * 1750 : 650, 0};
  BodyShape shape;
  shape.posture = posture;
  const BodyModel model = build_body_model(spec, spine, shape, s.l5_center);
  std::vector<Eigen::Vector3d> points;
  control_points(model, pose_vertebrae(model, spine, CvsmPose{}), points);
  XorCost cost(rig, 320, 240);
  s.frontal = cost.render(model, points, View::Frontal);
  s.lateral = cost.render(model, points, View::Lateral);
  return s;
}

TEST(TemplateFit, WalksAPerturbedTemplateBackToTheSubject) {
  const CvsmSpec truth = generic_cvsm_spec();
  const std::vector<TemplateSample> samples{sample_of(truth, SubjectPosture::Standing),
                                            sample_of(truth, SubjectPosture::Seated)};
  CvsmSpec start = truth;
  start.trunk[12].depth += 0.012;      // L1 ~21 mm too deep (the arms hide trunk widths)
  start.hip_y -= 0.012;                // hips ~21 mm low
  auto shoulder = std::find_if(start.parts.begin(), start.parts.end(), [](const auto& p) { return p.chain == "shoulder"; });
  ASSERT_NE(shoulder, start.parts.end());
  shoulder->half_width -= 0.010;

  const TemplateFit fit = fit_cvsm_template(CameraRig::default_rig(), start, samples);
  EXPECT_GT(fit.xor_before, 200);
  EXPECT_LT(fit.xor_after, fit.xor_before / 4);
  EXPECT_NEAR(fit.spec.trunk[12].depth, truth.trunk[12].depth, 0.004);
  EXPECT_NEAR(fit.spec.hip_y, truth.hip_y, 0.004);
  auto fitted_shoulder = std::find_if(fit.spec.parts.begin(), fit.spec.parts.end(), [](const auto& p) { return p.chain == "shoulder"; });
  EXPECT_NEAR(fitted_shoulder->half_width, (*std::find_if(truth.parts.begin(), truth.parts.end(), [](const auto& p) {
                return p.chain == "shoulder";
              })).half_width, 0.004);
}

TEST(TemplateFit, RewriteKeepsTheCommentsAndWritesEveryNumber) {
  CvsmSpec changed = generic_cvsm_spec();
  changed.trunk[0].half_width = 0.123;
  changed.trunk[16].spine_fraction = 0.456;
  changed.parts.back().front = 0.021;
  changed.hip_x = -0.015;
  const std::string text(generic_cvsm_toml());
  const std::string rewritten = rewrite_cvsm_values(text, changed);

  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), std::count(rewritten.begin(), rewritten.end(), '\n'));
  EXPECT_NE(rewritten.find("# Sources:"), std::string::npos);
  auto parsed = parse_cvsm_spec(rewritten, "rewritten");
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_DOUBLE_EQ(parsed->trunk[0].half_width, 0.123);
  EXPECT_DOUBLE_EQ(parsed->trunk[16].spine_fraction, 0.456);
  EXPECT_DOUBLE_EQ(parsed->parts.back().front, 0.021);
  EXPECT_DOUBLE_EQ(parsed->hip_x, -0.015);
  // Everything else as it was.
  EXPECT_DOUBLE_EQ(parsed->trunk[5].depth, generic_cvsm_spec().trunk[5].depth);
  EXPECT_DOUBLE_EQ(parsed->parts.front().y, generic_cvsm_spec().parts.front().y);
}

}  // namespace
}  // namespace spinewatch
