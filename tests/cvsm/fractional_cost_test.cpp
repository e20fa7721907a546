// The fit's cost with the outline's pixels covered in fractions
// (XorCost::evaluate_fractional, cvsm/edge_fractions.hpp) against a
// per-pixel reference; its continuity; the parabolic sweeps that refine a
// pose on it; and what the refinement does to a fit.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "coordinate_search.hpp"
#include "cvsm_fixtures.hpp"
#include "spinewatch/estimator/cvsm/segment_scan.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/cvsm/xor_cost.hpp"

namespace spinewatch {
namespace {

// The slow way: every segment's continuous spans from scan_segment, each
// sampled row's pixels covered by the length of their overlap with the
// union of those spans (a span clamped to the image's edge reaching past
// it), then |coverage − silhouette| summed over the sampled rows.
double reference_fractional(XorCost& cost, const BodyModel& model, const std::vector<Eigen::Vector3d>& points,
                            const Views& silhouettes, int step) {
  double total = 0;
  for (View view : kViews) {
    (void)cost.render(model, points, view);  // projects every plane the chains use
    const std::vector<PixelQ8>& proj = cost.projected(view);
    std::vector<RingSupport> support(model.planes.size());
    for (std::size_t p = 0; p < model.planes.size(); ++p)
      if (model.in_chain[p]) ring_support(proj.data() + p * kControlPoints, support[p]);
    std::vector<std::vector<std::pair<float, float>>> rows(kH);
    std::vector<std::int32_t> x0(kH + 3), x1(kH + 3);
    std::vector<float> left(kH + 3), right(kH + 3);
    for (const auto& chain : model.chains)
      for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
        const auto a = static_cast<std::size_t>(chain[i]), b = static_cast<std::size_t>(chain[i + 1]);
        const SegmentRows r = scan_segment({&support[a], proj.data() + a * kControlPoints},
                                           {&support[b], proj.data() + b * kControlPoints}, SpanImage{kW, kH, step},
                                           x0.data(), x1.data(), {left.data(), right.data()});
        for (int k = 0; k < r.count; ++k) {
          float l = left[static_cast<std::size_t>(k)], h = right[static_cast<std::size_t>(k)];
          if (h < l) continue;
          if (l <= 0) l = -0.5f;
          if (h >= kW - 1) h = kW - 0.5f;
          rows[static_cast<std::size_t>(r.first + k * step)].emplace_back(l, h);
        }
      }
    const BitMask& sil = view == View::Frontal ? silhouettes.frontal : silhouettes.lateral;
    for (int y = 0; y < kH; y += step) {
      auto& spans = rows[static_cast<std::size_t>(y)];
      std::sort(spans.begin(), spans.end());
      std::vector<std::pair<float, float>> merged;
      for (const auto& s : spans)
        if (!merged.empty() && s.first <= merged.back().second)
          merged.back().second = std::max(merged.back().second, s.second);
        else
          merged.push_back(s);
      for (int x = 0; x < kW; ++x) {
        double covered = 0;
        for (const auto& [l, h] : merged)
          covered += std::max(0.0, std::min<double>(h, x + 0.5) - std::max<double>(l, x - 0.5));
        total += std::abs(std::min(covered, 1.0) - (sil.get(x, y) ? 1.0 : 0.0));
      }
    }
  }
  return total;
}

TEST(FractionalCost, AgreesWithPerPixelCoverageOnRandomCandidates) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  const Views truth = render(rig, model, bend(25, 6, 4));
  XorCost cost(rig, kW, kH);
  cost.set_silhouettes(truth.frontal, truth.lateral);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-30, 60), lat(-25, 25), shift(-60, 60);
  std::vector<Eigen::Vector3d> pts;
  double worst = 0;
  for (int i = 0; i < 40; ++i) {
    CvsmPose p = bend(angle(rng), lat(rng), lat(rng) * 0.8);
    p.translation = {shift(rng), shift(rng) * 0.3, shift(rng)};
    // Some candidates half out of the frontal view, to cover the image's edge.
    if (i % 8 == 0) p.translation.z() = i % 16 == 0 ? 1000 : -1000;
    const int step = 1 << (i % 3);
    cost.set_row_step(step);
    control_points(model, pose_vertebrae(model, generic_spine_spec(), p), pts);
    const double fast = cost.evaluate_fractional(model, pts);
    const double ref = reference_fractional(cost, model, pts, truth, step);
    worst = std::max(worst, std::abs(fast - ref));
    ASSERT_NEAR(fast, ref, 0.05) << "candidate " << i << " row step " << step;
    // The fractions only move the outline's pixels: the whole-pixel count
    // is within the model's boundary length of it.
    EXPECT_NEAR(fast, static_cast<double>(cost.evaluate(model, pts).total()), 0.5 * static_cast<double>(kH) * 8);
  }
  std::printf("worst fast/reference difference: %.4f px\n", worst);
}

// Moving the model sideways in the frontal view by a fiftieth of a
// millimetre at a time (a thirtieth of a pixel; in the lateral view it
// moves in depth). The cost rises as the model leaves the silhouette;
// what matters is how: the whole-pixel count in steps of whole pixels as
// span ends cross pixel centres, the fractional cost smoothly but where a
// row appears or goes (the rows are still sampled at their centres).
// Measured as the summed size of the second differences: a staircase
// scores its every step twice, a smooth rise next to nothing.
TEST(FractionalCost, FollowsASubPixelMotionThatTheWholePixelCountSteps) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  const Views truth = render(rig, model, bend(20, 0, 0));
  XorCost cost(rig, kW, kH);
  cost.set_silhouettes(truth.frontal, truth.lateral);
  std::vector<Eigen::Vector3d> pts;
  std::vector<double> whole, fractional;
  for (int i = 0; i <= 400; ++i) {
    CvsmPose p = bend(20, 0, 0);
    p.translation.z() = 2 + 0.02 * i;  // world Z: the frontal view's horizontal
    control_points(model, pose_vertebrae(model, generic_spine_spec(), p), pts);
    fractional.push_back(cost.evaluate_fractional(model, pts));
    whole.push_back(static_cast<double>(cost.evaluate(model, pts).total()));
  }
  auto roughness = [](const std::vector<double>& c) {
    double sum = 0;
    for (std::size_t i = 1; i + 1 < c.size(); ++i) sum += std::abs(c[i + 1] - 2 * c[i] + c[i - 1]);
    return sum;
  };
  const double rise = fractional.back() - fractional.front();
  std::printf("over 8 mm the cost rises by %.0f px; second differences sum to %.0f px whole, %.1f px fractional\n", rise,
              roughness(whole), roughness(fractional));
  EXPECT_GT(rise, 100.0);
  EXPECT_NEAR(whole.back() - whole.front(), rise, 0.1 * rise);
  // Measured 0.17 of the staircase's: what is left is mostly the lateral
  // view, where the depth change grows the outline across row centres.
  EXPECT_LT(roughness(fractional), 0.25 * roughness(whole));
}

// A separable quadratic with its minimum within the first steps: one sweep
// lands on it (the parabola through three points of a parabola is exact).
TEST(ParabolicSweeps, OneSweepFindsTheMinimumOfASeparableQuadratic) {
  const std::array<double, 3> minimum{0.7, -1.3, 2.9};
  int calls = 0;
  auto cost = [&](const std::array<double, 3>& x) {
    ++calls;
    return 3 * std::pow(x[0] - minimum[0], 2) + 0.5 * std::pow(x[1] - minimum[1], 2) + 8 * std::pow(x[2] - minimum[2], 2);
  };
  std::array<double, 3> x{0, 0, 2};
  double best = cost(x);
  calls = 0;
  const int evaluations = cvsm_detail::parabolic_sweeps(x, best, std::array<double, 3>{1, 2, 1}, 1, cost);
  EXPECT_EQ(evaluations, calls);
  EXPECT_LE(evaluations, 9);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(x[i], minimum[i], 1e-9) << i;
  EXPECT_NEAR(best, 0.0, 1e-12);
}

// Whatever the cost, the result is never worse than the start and `best`
// is the cost of the parameters returned.
TEST(ParabolicSweeps, NeverEndsWorseThanItStartedOnABumpyCost) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> start(-3, 3);
  auto bumpy = [](const std::array<double, 2>& x) {
    return x[0] * x[0] + 2 * x[1] * x[1] + 1.5 * x[0] * x[1] + 0.8 * std::sin(7 * x[0]) * std::cos(5 * x[1]) +
           0.3 * std::floor(3 * x[1]);
  };
  for (int i = 0; i < 200; ++i) {
    std::array<double, 2> x{start(rng), start(rng)};
    const double first = bumpy(x);
    double best = first;
    cvsm_detail::parabolic_sweeps(x, best, std::array<double, 2>{0.5, 0.5}, 1 + i % 3, bumpy);
    EXPECT_LE(best, first);
    EXPECT_DOUBLE_EQ(best, bumpy(x));
  }
}

// The refinement on the self-consistency sequence of cvsm_test (another
// subject's model drawn by the OpenCV reference, bending and back): the
// fit comes out closer to that subject's neck and waist, with more cost
// evaluations per pair.
TEST(CvsmRefinement, BringsTheFitCloserToAnotherSubjectsPose) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel subject = other_subject();
  std::vector<CvsmPose> poses(10, CvsmPose{});
  for (int i = 0; i <= 40; ++i) {
    const double s = 0.5 - 0.5 * std::cos(M_PI * i / 20.0);
    poses.push_back(bend(50 * s, 12 * s, 6 * s));
  }
  struct Run {
    double error = 0;  // neck and waist, mean over the tracked pairs, mm
    double candidates = 0;
    int lost = 0;
  };
  auto run = [&](int sweeps) {
    CvsmOptions options;
    options.spine_placement = SpinePlacementMode::Generic;
    options.refine_sweeps = sweeps;
    CvsmTracker tracker(rig, options);
    Run out;
    int tracked = 0;
    for (const CvsmPose& p : poses) {
      const Views v = render(rig, subject, p);
      const CvsmResult r = tracker.track(v.frontal, v.lateral);
      if (r.state == TrackingState::Init) continue;
      if (r.state == TrackingState::Lost) {
        ++out.lost;
        continue;
      }
      const SpinePose truth = pose_vertebrae(subject, generic_spine_spec(), p);
      out.error += (r.neck - truth[kNeckIndex].body_center).norm() + (r.waist - truth[kWaistIndex].body_center).norm();
      out.candidates += r.fit.candidates.value_or(0);
      ++tracked;
    }
    out.error /= 2.0 * std::max(1, tracked);
    out.candidates /= std::max(1, tracked);
    return out;
  };
  const Run plain = run(0), refined = run(1);
  std::printf("neck and waist: %.2f mm with %.1f evaluations a pair, refined %.2f mm with %.1f\n", plain.error,
              plain.candidates, refined.error, refined.candidates);
  EXPECT_EQ(plain.lost, 0);
  EXPECT_EQ(refined.lost, 0);
  EXPECT_LT(refined.error, plain.error);
  EXPECT_GT(refined.candidates, plain.candidates + 8);
}

// The refinement moves a pose by at most a few steps and only to a lower
// cost; whether a pair is lost is still decided on the whole-pixel cost of
// the full model afterwards. Silhouettes no body fits (a block) stay lost
// with it on, and a half-hidden person does not pull the fit far.
TEST(CvsmRefinement, SilhouettesNoBodyFitsStayLost) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel subject = other_subject();
  const Views upright = render(rig, subject, CvsmPose{});
  BitMask block(kW, kH);
  for (int y = 30; y < kH; ++y)
    for (int x = 130; x < 190; ++x) block.set(x, y, true);
  for (int sweeps : {0, 1}) {
    CvsmOptions options;
    options.spine_placement = SpinePlacementMode::Generic;
    options.refine_sweeps = sweeps;
    CvsmTracker tracker(rig, options);
    CvsmResult good;
    for (int i = 0; i < 12; ++i) good = tracker.track(upright.frontal, upright.lateral);
    ASSERT_EQ(good.state, TrackingState::Tracking) << sweeps;
    for (int i = 0; i < 3; ++i) {
      const CvsmResult r = tracker.track(block, block);
      EXPECT_EQ(r.state, TrackingState::Lost) << "sweeps " << sweeps << ", pair " << i << ": cost " << r.fit.cost;
    }
    // Back to the person, then half of them hidden in the frontal view.
    for (int i = 0; i < 3; ++i) good = tracker.track(upright.frontal, upright.lateral);
    ASSERT_EQ(good.state, TrackingState::Tracking) << sweeps;
    BitMask half = upright.frontal;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < 160; ++x) half.set(x, y, false);
    const CvsmResult r = tracker.track(half, upright.lateral);
    if (r.state != TrackingState::Lost) {
      EXPECT_LT((r.waist - good.waist).norm(), 60.0) << sweeps;
      EXPECT_LT((r.neck - good.neck).norm(), 60.0) << sweeps;
    }
  }
}

}  // namespace
}  // namespace spinewatch
