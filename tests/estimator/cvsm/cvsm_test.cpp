// The CVSM: generic model file, fixed-point projection, the fast XOR cost
// against the OpenCV float reference, and the tracker on silhouettes
// rendered from a model of a different subject (self-consistency).
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "cvsm/fixed_camera.hpp"
#include "cvsm/segment_scan.hpp"
#include "cvsm/xor_cost.hpp"
#include "cvsm_fixtures.hpp"
#include "cvsm_reference.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"

namespace spinewatch {
namespace {

TEST(CvsmSpec, GenericModelParses) {
  const CvsmSpec& spec = generic_cvsm_spec();
  EXPECT_GT(spec.trunk[5].depth, spec.trunk[0].depth);
  EXPECT_GE(spec.parts.size(), 10u);
  const BodyModel m = build_body_model(spec, generic_spine_spec(), BodyShape{}, {0, 1006, 0});
  EXPECT_EQ(m.local_points.size(), m.planes.size() * kControlPoints);
  EXPECT_EQ(m.chains.size(), 5u);  // trunk with pelvis and head, two arms, two legs
}

TEST(CvsmSpec, BadFileNamesLineAndField) {
  std::string text(generic_cvsm_toml());
  // T1's half width (the first number of the first [[trunk]]) made absurd.
  const auto pos = text.find("half_width = ", text.find("[[trunk]]"));
  ASSERT_NE(pos, std::string::npos);
  text.replace(pos, 18, "half_width = 0.900");
  const auto r = parse_cvsm_spec(text, "bad.toml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("bad.toml:"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("trunk[0].half_width"), std::string::npos) << r.error().message;
  EXPECT_FALSE(parse_cvsm_spec("[model", "x.toml").ok());
}

TEST(FixedCamera, ProjectsWithinTheStatedBound) {
  const CameraRig rig = CameraRig::default_rig();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> xz(-600, 600), y(0, 2000);
  for (const CameraModel* cam : {&rig.frontal, &rig.lateral}) {
    const FixedCamera fixed(*cam);
    ASSERT_TRUE(fixed.integer_path());
    double worst = 0;
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector3d p(xz(rng), y(rng), xz(rng));
      PixelQ8 q;
      ASSERT_TRUE(fixed.project(p, q));
      const Eigen::Vector2d ref = *cam->project(p);
      worst = std::max({worst, std::abs(q.u / 256.0 - ref.x()), std::abs(q.v / 256.0 - ref.y())});
    }
    EXPECT_LT(worst, 0.025);
  }
  PixelQ8 q;
  EXPECT_FALSE(FixedCamera(rig.frontal).project({2500, 1000, 0}, q));  // behind the camera
}

// A point just in front of a camera, or far out where a lens's distortion
// polynomial runs away, projects anywhere: both paths clamp it to
// ±kQ8Limit, where a ring's packed keys stay exact (segment_scan.hpp).
// Unclamped, a real camera's distortion (caliscope's cam_2, imported) put
// a point so far out that the scan read past a ring's points (ASan).
TEST(FixedCamera, ClampsPointsFarOutsideTheImage) {
  CameraModel distorted = CameraRig::default_rig().frontal;
  distorted.dist_coeffs[0] = 0.4;  // k1
  distorted.dist_coeffs[1] = 0.9;  // k2
  ASSERT_TRUE(distorted.has_distortion());
  for (const CameraModel& cam : {CameraRig::default_rig().frontal, distorted}) {
    const FixedCamera fixed(cam);
    // 2 mm in front of the camera's plane, 1.5 m off its axis.
    const Eigen::Vector3d near_plane = cam.R.transpose() * (Eigen::Vector3d(1500, 900, 2) - cam.t);
    PixelQ8 q;
    ASSERT_TRUE(fixed.project(near_plane, q));
    EXPECT_LE(std::abs(q.u), kQ8Limit);
    EXPECT_LE(std::abs(q.v), kQ8Limit);
    EXPECT_EQ(std::abs(q.u), kQ8Limit) << "far outside: held at the limit";
  }
}

TEST(XorCost, AgreesWithOpenCvReferenceOnRandomCandidates) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  const Views truth = render(rig, model, bend(30, 8, 5));
  const cv::Mat sf = test::to_mat(truth.frontal), sl = test::to_mat(truth.lateral);
  XorCost cost(rig, kW, kH);
  cost.set_silhouettes(truth.frontal, truth.lateral);
  const auto silhouette = static_cast<double>(truth.frontal.count() + truth.lateral.count());
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> angle(-30, 60), lat(-25, 25), shift(-60, 60);
  std::vector<Eigen::Vector3d> pts;
  cv::Mat scratch, diff;
  double worst = 0;
  for (int i = 0; i < 60; ++i) {
    CvsmPose p = bend(angle(rng), lat(rng), lat(rng) * 0.8);
    p.translation = {shift(rng), shift(rng) * 0.3, shift(rng)};
    control_points(model, pose_vertebrae(model, generic_spine_spec(), p), pts);
    const XorCounts fast = cost.evaluate(model, pts);
    ASSERT_FALSE(fast.pruned);
    const std::int64_t ref = test::reference_xor(rig.frontal, model, pts, sf, scratch, diff) +
                             test::reference_xor(rig.lateral, model, pts, sl, scratch, diff);
    // Pixels compared: the silhouettes' and the model's, both views.
    const double compared = silhouette + static_cast<double>(cost.render(model, pts, View::Frontal).count() +
                                                             cost.render(model, pts, View::Lateral).count());
    worst = std::max(worst, std::abs(static_cast<double>(fast.total() - ref)) / compared);
  }
  EXPECT_LT(worst, 0.005) << "fast and reference XOR differ by more than 0.5 % of the pixels compared";
  std::printf("worst fast/reference XOR difference: %.3f %% of the pixels compared\n", 100 * worst);
}

// The fast path projects in float, four points at a time: every control
// point of random candidates lands within the Q8 rounding (1/512 px) plus
// 2e-4 px of the double projection.
TEST(XorCost, ProjectsLikeTheCameraModel) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  XorCost cost(rig, kW, kH);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-30, 60), lat(-25, 25), shift(-300, 300);
  std::vector<Eigen::Vector3d> pts;
  double worst = 0;
  for (int i = 0; i < 50; ++i) {
    CvsmPose p = bend(angle(rng), lat(rng), lat(rng));
    p.translation = {shift(rng), shift(rng) * 0.3, shift(rng)};
    control_points(model, pose_vertebrae(model, generic_spine_spec(), p), pts);
    for (View view : kViews) {
      (void)cost.render(model, pts, view);
      const CameraModel& cam = view == View::Frontal ? rig.frontal : rig.lateral;
      for (std::size_t k = 0; k < pts.size(); ++k) {
        const Eigen::Vector2d ref = *cam.project(pts[k]);
        const PixelQ8 q = cost.projected(view)[k];
        worst = std::max({worst, std::abs(q.u / 256.0 - ref.x()), std::abs(q.v / 256.0 - ref.y())});
      }
    }
  }
  EXPECT_LT(worst, 1.0 / 512 + 2e-4);
  std::printf("worst projection error: %.5f px\n", worst);
}

// Rings flattened to a point or a horizontal line have no sides that
// bound columns: the segment still covers exactly the pixels whose centres
// lie within half a pixel (|du| + |dv| ≤ ½), as fillPoly's outline does.
TEST(SegmentScan, DegenerateRingsCoverTheirOwnPixels) {
  auto span_of = [](const std::array<PixelQ8, kControlPoints>& ring, int& first, std::vector<std::pair<int, int>>& spans) {
    RingSupport support;
    ring_support(ring.data(), support);
    std::vector<std::int32_t> x0(kH + 3), x1(kH + 3);
    const SegmentRows rows = scan_segment({&support, ring.data()}, {&support, ring.data()}, SpanImage{kW, kH, 1}, x0.data(), x1.data());
    first = rows.first;
    spans.clear();
    for (int i = 0; i < rows.count; ++i) spans.emplace_back(x0[static_cast<std::size_t>(i)], x1[static_cast<std::size_t>(i)]);
  };
  std::array<PixelQ8, kControlPoints> ring;
  int first = 0;
  std::vector<std::pair<int, int>> spans;

  ring.fill(PixelQ8{100 * 256 + 26, 50 * 256 + 26});  // (100.1, 50.1)
  span_of(ring, first, spans);
  EXPECT_EQ(first, 50);
  EXPECT_EQ(spans, (std::vector<std::pair<int, int>>{{100, 100}}));

  for (int k = 0; k < kControlPoints; ++k) ring[static_cast<std::size_t>(k)] = PixelQ8{(100 + (k * 40) / 11) * 256, 50 * 256};
  span_of(ring, first, spans);
  EXPECT_EQ(first, 50);
  EXPECT_EQ(spans, (std::vector<std::pair<int, int>>{{100, 140}}));

  // Off the left edge and below the image: nothing but the clipped part.
  ring.fill(PixelQ8{-5 * 256, 120 * 256});
  ring[0] = PixelQ8{3 * 256, 120 * 256};
  span_of(ring, first, spans);
  EXPECT_EQ(spans, (std::vector<std::pair<int, int>>{{0, 3}}));
  ring.fill(PixelQ8{10 * 256, (kH + 2) * 256});
  span_of(ring, first, spans);
  EXPECT_TRUE(spans.empty());
}

TEST(XorCost, PrunedCountIsALowerBoundAboveTheLimit) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  const Views truth = render(rig, model, CvsmPose{});
  XorCost cost(rig, kW, kH);
  cost.set_silhouettes(truth.frontal, truth.lateral);
  std::vector<Eigen::Vector3d> pts;
  control_points(model, pose_vertebrae(model, generic_spine_spec(), bend(45, 0, 0)), pts);
  const XorCounts exact = cost.evaluate(model, pts);
  ASSERT_GT(exact.total(), 200);
  const XorCounts pruned = cost.evaluate(model, pts, exact.total() / 4);
  EXPECT_TRUE(pruned.pruned);
  EXPECT_GT(pruned.total(), exact.total() / 4);
  EXPECT_LE(pruned.total(), exact.total());
  // The model rendered from the true pose is (almost) its own silhouette.
  control_points(model, pose_vertebrae(model, generic_spine_spec(), CvsmPose{}), pts);
  EXPECT_LT(cost.evaluate(model, pts).cost(), 0.02);  // boundary pixels only
}

// The incremental state (cached projections, ring supports, segment
// spans, row sampling) must never change a result: a cost that has seen other candidates, other models and another
// row step draws exactly what a fresh one draws.
TEST(XorCost, WarmCacheDrawsWhatAFreshCostDraws) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  const BodyModel thin = thin_trunk(model, 4);
  XorCost warm(rig, kW, kH);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> angle(-30, 60), lat(-25, 25), shift(-60, 60);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 40; ++i) {
    CvsmPose p = bend(angle(rng), lat(rng), lat(rng) * 0.8);
    p.translation = {shift(rng), shift(rng) * 0.3, shift(rng)};
    control_points(model, pose_vertebrae(model, generic_spine_spec(), p), pts);
    warm.set_row_step(i % 3 == 0 ? 4 : 1);
    const BodyModel& m = i % 2 ? thin : model;
    (void)warm.render(m, pts, View::Frontal);
    (void)warm.render(m, pts, View::Lateral);
    warm.set_row_step(1);
    for (View view : kViews) {
      XorCost fresh(rig, kW, kH);
      ASSERT_TRUE(warm.render(m, pts, view) == fresh.render(m, pts, view)) << "candidate " << i << " view " << to_string(view);
    }
  }
}

// The search's outline: every 4th vertebra ring and T1 and L5, every other
// plane kept; the same planes and points, so one set of control points
// serves both, and a thinned model fills only the planes it uses.
TEST(CvsmModel, ThinTrunkKeepsEveryFourthVertebraAndTheEnds) {
  const BodyModel model = other_subject();
  const BodyModel thin = thin_trunk(model, 4);
  EXPECT_EQ(thin.planes.size(), model.planes.size());
  EXPECT_EQ(thin.chains.size(), model.chains.size());
  for (std::size_t c = 1; c < model.chains.size(); ++c) EXPECT_EQ(thin.chains[c], model.chains[c]);
  std::vector<int> kept_vertebrae, other_full, other_thin;
  for (const int p : model.chains[0])
    if (!model.planes[static_cast<std::size_t>(p)].vertebra) other_full.push_back(p);
  for (const int p : thin.chains[0]) {
    const ControlPlane& plane = thin.planes[static_cast<std::size_t>(p)];
    if (plane.vertebra)
      kept_vertebrae.push_back(plane.frame);
    else
      other_thin.push_back(p);
  }
  std::sort(kept_vertebrae.begin(), kept_vertebrae.end());
  EXPECT_EQ(kept_vertebrae, (std::vector<int>{0, 4, 8, 12, 16}));  // T1, T5, T9, L1, L5
  EXPECT_EQ(other_thin, other_full);  // pelvis, shoulders and head untouched
  EXPECT_EQ(thin_trunk(model, 1).chains, model.chains);

  // Planes the thinned chains skip keep whatever was there.
  std::vector<Eigen::Vector3d> pts(model.local_points.size(), Eigen::Vector3d(1e9, 1e9, 1e9));
  control_points(thin, pose_vertebrae(thin, generic_spine_spec(), CvsmPose{}), pts);
  std::vector<Eigen::Vector3d> full;
  control_points(model, pose_vertebrae(model, generic_spine_spec(), CvsmPose{}), full);
  int untouched = 0;
  for (std::size_t p = 0; p < model.planes.size(); ++p) {
    const bool used = std::find(thin.chains[0].begin(), thin.chains[0].end(), static_cast<int>(p)) != thin.chains[0].end() ||
                      model.planes[p].frame >= kLegLeftFrame || !model.planes[p].vertebra;
    for (int k = 0; k < kControlPoints; ++k) {
      const std::size_t i = p * kControlPoints + static_cast<std::size_t>(k);
      if (used) {
        EXPECT_EQ(pts[i], full[i]) << "plane " << p;
      } else {
        EXPECT_EQ(pts[i].x(), 1e9) << "plane " << p;
        ++untouched;
      }
    }
  }
  EXPECT_EQ(untouched, 12 * kControlPoints);  // 17 vertebra rings, 5 kept
}

// These subjects are CVSM body models on the generic spine: tracked with
// the same placement (the measured one is tests/tools/population's).
CvsmOptions generic_spine_options() {
  CvsmOptions o;
  o.spine_placement = SpinePlacementMode::Generic;
  return o;
}

TEST(CvsmTracker, TracksAnotherSubjectsModelThroughABend) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel subject = other_subject();
  std::vector<CvsmPose> poses(10, CvsmPose{});
  for (int i = 0; i <= 40; ++i) {
    const double s = 0.5 - 0.5 * std::cos(M_PI * i / 20.0);  // 0 → 1 → 0
    poses.push_back(bend(50 * s, 12 * s, 6 * s));
  }
  CvsmTracker tracker(rig, generic_spine_options());
  const SequenceErrors e = track_sequence(tracker, rig, subject, poses);
  ASSERT_NE(tracker.subject_model(), nullptr);
  EXPECT_NEAR(tracker.subject_model()->shape.height_mm, 1620, 30);
  EXPECT_EQ(e.lost, 0);
  EXPECT_LT(e.neck_mean, 10.0);
  EXPECT_LT(e.waist_mean, 10.0);
  EXPECT_LT(e.neck_max, 25.0);
  EXPECT_LT(e.waist_max, 25.0);
  std::printf("self-consistency: neck mean %.1f max %.1f, waist mean %.1f max %.1f mm\n", e.neck_mean, e.neck_max,
              e.waist_mean, e.waist_max);
}

TEST(CvsmTracker, NoPersonIsLostAndItRecoversAfterAJump) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel subject = other_subject();
  CvsmTracker tracker(rig, generic_spine_options());
  const Views upright = render(rig, subject, CvsmPose{});
  for (int i = 0; i < 10; ++i) tracker.track(upright.frontal, upright.lateral);
  EXPECT_EQ(tracker.track(upright.frontal, upright.lateral).state, TrackingState::Tracking);

  const BitMask empty(kW, kH);
  const CvsmResult none = tracker.track(empty, empty);
  EXPECT_EQ(none.state, TrackingState::Lost);
  EXPECT_EQ(none.fit.flag.value_or(""), "no_person");
  EXPECT_FALSE(none.valid());

  // The person reappears far into a bend: tracking must be back within 5 frames.
  const CvsmPose far = bend(45, -15, 0);
  const Views bent = render(rig, subject, far);
  const SpinePose truth = pose_vertebrae(subject, generic_spine_spec(), far);
  int frames = 0;
  CvsmResult r;
  do {
    r = tracker.track(bent.frontal, bent.lateral);
    ++frames;
  } while (r.state != TrackingState::Tracking && frames < 5);
  EXPECT_EQ(r.state, TrackingState::Tracking);
  EXPECT_LT((r.waist - truth[kWaistIndex].body_center).norm(), 20.0);
  EXPECT_LT((r.neck - truth[kNeckIndex].body_center).norm(), 25.0);
}

TEST(CvsmTracker, FlaggedAndHalfOccludedSilhouettesNeverJumpWildly) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel subject = other_subject();
  CvsmTracker tracker(rig, generic_spine_options());
  const Views upright = render(rig, subject, CvsmPose{});
  CvsmResult good;
  for (int i = 0; i < 12; ++i) good = tracker.track(upright.frontal, upright.lateral);
  ASSERT_EQ(good.state, TrackingState::Tracking);

  // Half the person hidden in the frontal view (left half cut away).
  BitMask half = upright.frontal;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < 160; ++x) half.set(x, y, false);
  SilhouetteResult f, l;
  f.status = SilhouetteStatus::Occluded;
  f.mask = half;
  f.pixels = half.count();
  l.status = SilhouetteStatus::Person;
  l.mask = upright.lateral;
  l.pixels = l.mask.count();
  const CvsmResult r = tracker.track(f, l);
  EXPECT_EQ(r.fit.flag.value_or(""), "occluded");
  if (r.state != TrackingState::Lost) {
    EXPECT_LT((r.waist - good.waist).norm(), 60.0);
    EXPECT_LT((r.neck - good.neck).norm(), 60.0);
  }
  f.status = SilhouetteStatus::NoPerson;
  EXPECT_EQ(tracker.track(f, l).state, TrackingState::Lost);
  f.status = SilhouetteStatus::TwoBlobs;
  f.mask = upright.frontal;
  EXPECT_EQ(tracker.track(f, l).fit.flag.value_or(""), "two_blobs");
  // Mismatched sizes are no person, not a crash.
  EXPECT_EQ(tracker.track(BitMask(16, 16), upright.lateral).state, TrackingState::Lost);
}

}  // namespace
}  // namespace spinewatch
