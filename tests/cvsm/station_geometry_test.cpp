// The CVSM through rolled and steeply tilted cameras (issue 31, "any
// calibrated geometry"; docs/cvsm.md, "Measuring along the world's
// vertical"): the default phantom subject, a measured adult with the
// estimator's default (measured) spine placement, bending forward under
// the phantom's station geometries, rendered in memory and fitted frame by
// frame from its silhouettes.
#include <algorithm>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "test_support.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch {
namespace {

// A tracking posture with a vertebra farther than this from the truth is
// confidently wrong (issue 31).
constexpr double kWrongMm = 50;

struct GeometryRun {
  int person_frames = 0, tracking = 0, lost = 0;
  int wrong = 0;           // tracking postures with a vertebra > kWrongMm off
  double worst_mm = 0;     // of any vertebra of any tracking posture
  double neck_sum = 0;     // over the tracking postures
  double neck_mean() const { return tracking > 0 ? neck_sum / tracking : 0.0; }
};

// `frames` person frames of flexion after the ten empty ones, seed 1.
GeometryRun run_station(const phantom::StationGeometry& geometry, int frames, const CvsmOptions& options = {}) {
  GeometryRun run;
  auto subject = phantom::load_subject(test::source_dir() + "/config/subjects/ansur-15936.json");
  EXPECT_TRUE(subject.ok()) << subject.error().message;
  if (!subject.ok()) return run;
  phantom::PhantomOptions po;
  po.scenario = "flexion";
  po.subject = *subject;
  po.frames = frames;
  po.station = geometry;
  auto seq = phantom::PhantomSequence::create(po);
  EXPECT_TRUE(seq.ok()) << seq.error().message;
  if (!seq.ok()) return run;
  auto view_of = [](const cv::Mat& m) { return LumaView{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; };
  SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
  CvsmTracker tracker(seq->options().rig, options);
  for (int i = 0; i < seq->frame_count(); ++i) {
    const phantom::PhantomFrame f = seq->render(i);
    const CvsmResult r = tracker.track(frontal.extract(view_of(f.luma[0])), lateral.extract(view_of(f.luma[1])));
    if (!f.truth.neck) continue;  // an empty frame
    ++run.person_frames;
    if (r.state == TrackingState::Lost) ++run.lost;
    if (r.state != TrackingState::Tracking) continue;
    ++run.tracking;
    double worst = 0;
    for (std::size_t v = 0; v < kVertebraCount; ++v)
      worst = std::max(worst, (r.vertebrae[v].body_center - (*f.truth.vertebrae)[v].body_center).norm());
    run.worst_mm = std::max(run.worst_mm, worst);
    run.wrong += worst > kWrongMm;
    run.neck_sum += (r.neck - *f.truth.neck).norm();
  }
  std::printf("tracking %d / lost %d of %d person frames; neck mean %.1f mm; worst vertebra %.0f mm (%d > %.0f)\n",
              run.tracking, run.lost, run.person_frames, run.neck_mean(), run.worst_mm, run.wrong, kWrongMm);
  return run;
}

TEST(StationGeometry, RolledCamerasTrackTheBendWithoutAConfidentlyWrongPosture) {
  // Measured on this render: neck mean 8.1 mm, worst vertebra 20 mm. With
  // the first silhouettes read along the image's own rows the subject model
  // came out about 90 mm short: neck mean 94 mm, all 21 tracking postures
  // 85–98 mm off.
  phantom::StationGeometry geometry;
  geometry.roll_deg = 25;
  const GeometryRun run = run_station(geometry, 30);
  ASSERT_EQ(run.person_frames, 30);
  EXPECT_EQ(run.wrong, 0) << "worst " << run.worst_mm << " mm";
  EXPECT_GE(run.tracking, 21);  // every pair after the subject model's nine init pairs
  EXPECT_LE(run.neck_mean(), 14.0);
}

TEST(StationGeometry, RolledCamerasWithArticulatedLimbs) {
  // Measured on this render: neck mean 14.5 mm, worst vertebra 38 mm
  // (along the image's rows: 95.6 mm, all 21 tracking postures off).
  phantom::StationGeometry geometry;
  geometry.roll_deg = 25;
  CvsmOptions options;
  options.limbs = LimbMode::Articulated;
  const GeometryRun run = run_station(geometry, 30, options);
  ASSERT_EQ(run.person_frames, 30);
  EXPECT_EQ(run.wrong, 0) << "worst " << run.worst_mm << " mm";
  EXPECT_GE(run.tracking, 21);
  EXPECT_LE(run.neck_mean(), 22.0);
}

TEST(StationGeometry, SteepCamerasKeepTheirShareAndAreNeverConfidentlyWrong) {
  // Tilted 45° down the bent trunk is foreshortened to half its upright
  // outline and the cost passes lost_cost near the deepest bend: those
  // pairs are lost, not guessed. Measured on this render: 19 of 30
  // tracking (the share asserted), 2 lost, neck mean 17.2 mm, worst
  // vertebra 42 mm. The rows of a camera looking down are level, so the
  // rectification leaves this fit as it was.
  phantom::StationGeometry geometry;
  geometry.tilt_deg = 45;
  const GeometryRun run = run_station(geometry, 30);
  ASSERT_EQ(run.person_frames, 30);
  EXPECT_EQ(run.wrong, 0) << "worst " << run.worst_mm << " mm";
  EXPECT_GE(run.tracking, 19);
}

}  // namespace
}  // namespace spinewatch
