// A seated person behind a desk the stored background holds: the frontal
// silhouette ends at the desk's edge (docs/cvsm.md, "Occluded lower
// body"). Short renders of one subject through the CVSM; the truth is the
// phantom's.
#include <cstdio>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/fit_flags.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "test_support.hpp"
#include "trust_run.hpp"

namespace spinewatch {
namespace {

test::TrustRun run_at_desk(const std::string& scenario, const std::string& subject_name, int frames) {
  phantom::PhantomOptions po;
  po.scenario = scenario;
  po.subject = test::load_named_subject(subject_name);
  po.frames = frames;
  po.seed = 3;
  po.desk = true;
  return test::track_for_trust(po, test::generic_subject_options(), scenario + " at the desk, " + subject_name);
}

// Without the occluder's edge the fit dragged the pelvis down to explain
// the hidden legs (the waist 180–210 mm off, docs/accuracy.md) or lost
// the person; with it the trunk's own outline decides, and a pair whose
// lower body neither view sees is lost, not published.
// (The phantom's tall subject is not asserted: it is still fitted
// standing behind the desk, docs/cvsm.md, "Occluded lower body".)
TEST(Occlusion, BehindADeskNoTrackedPostureIsConfidentlyWrong) {
  for (const char* scenario : {"seated_flexion", "typing"}) {
    const test::TrustRun run = run_at_desk(scenario, "petite", 30);
    EXPECT_EQ(run.wrong, 0) << scenario;
    EXPECT_LE(run.worst_mm, 45.0) << scenario;  // measured 36 and 9
  }
}

// One of the varied phantom's rows (scripts/baseline-fit: seed 1, 60
// person frames) for a measured adult of the ANSUR II test set, at the desk.
phantom::PhantomOptions ansur_at_desk(const std::string& scenario, int id) {
  phantom::PhantomOptions po;
  po.scenario = scenario;
  auto subject = phantom::load_ansur_subject("ansur:" + std::to_string(id),
                                             test::source_path(std::string(anthropometry::kAnsurRelativeDir)));
  EXPECT_TRUE(subject.ok()) << subject.error().message;
  if (subject.ok()) po.subject = *subject;
  po.frames = 60;
  po.seed = 1;
  po.desk = true;
  return po;
}

// Standing or seated, as chosen on the first pair with a person.
std::optional<SubjectPosture> chosen_posture(const phantom::PhantomOptions& po) {
  auto seq = phantom::PhantomSequence::create(po);
  EXPECT_TRUE(seq.ok()) << seq.error().message;
  if (!seq.ok()) return std::nullopt;
  auto view_of = [](const cv::Mat& m) { return LumaView{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; };
  SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
  CvsmTracker tracker(seq->options().rig, CvsmOptions{});
  for (int i = 0; i < seq->frame_count(); ++i) {
    const phantom::PhantomFrame f = seq->render(i);
    tracker.track(frontal.extract(view_of(f.luma[0])), lateral.extract(view_of(f.luma[1])));
    if (const BodyModel* model = tracker.subject_model()) return model->shape.posture;
  }
  return std::nullopt;
}

// The tallest test subject (11953, 1838 mm, 104 kg) seated behind the
// desk: the desk's edge cuts his frontal silhouette across the trunk and
// his forearms resting on it beside the trunk. Hidden only under the
// trunk's straight run, his seated thighs were charged under the forearms
// and a standing model squeezed to his seated crown (1382–1394 mm) won:
// every pair was lost or, where a view was left, published 180 mm off.
// Compared with all the edge cuts hidden (posture_hidden.hpp), the seated
// model wins, at 1912–1972 mm.
TEST(Occlusion, TheTallestTestSubjectBehindADeskIsFittedSeated) {
  for (const char* scenario : {"seated_flexion", "typing"}) {
    const std::optional<SubjectPosture> posture = chosen_posture(ansur_at_desk(scenario, 11953));
    ASSERT_TRUE(posture) << scenario;
    EXPECT_EQ(*posture, SubjectPosture::Seated) << scenario;
  }
}

// With his seated model, the pairs whose lateral view shows his thighs on
// the seat could be published (31 of 60 tracking, worst vertebra 33 mm,
// while the facing check weighed him against his mirror turned 180°
// only). Weighed against the reflection of his heading and 30° either side
// (docs/cvsm.md, "Turned away from the range"), his mirror fits the seated
// model better by about 2 % over the building pairs, and he is held
// facing_away: every pair lost (29 facing_away, the rest lower_body_hidden
// where both views end on the desk), none wrong —
// the seated model still tells no side from the other here. What this
// asserts is that nothing published for him is wrong and that the seated
// model is what is weighed (the previous test).
TEST(Occlusion, TheTallestTestSubjectBehindADeskIsNeverPublishedWrong) {
  int facing_away = 0;
  const test::TrustRun run = test::track_for_trust(
      ansur_at_desk("seated_flexion", 11953), CvsmOptions{}, "seated_flexion at the desk, ansur 11953", {},
      [&](const phantom::PhantomFrame&, const CvsmResult& r) {
        facing_away += r.state == TrackingState::Lost && r.fit.flag == std::string(kFacingAwayFlag);
      });
  EXPECT_EQ(run.wrong, 0) << "worst " << run.worst_mm << " mm";
  std::printf("  facing_away: %d pairs\n", facing_away);
  // Measured: 29 of the 51 pairs after the model facing_away, 0 tracking.
  EXPECT_GE(run.tracking + facing_away, 12);
}

// A tall, thin worker (ANSUR 28048, 1930 mm, 69 kg) seated behind the
// desk: from the side his thighs go under it and its end cuts them on a
// steep line, which the lower outline's edge does not find. Charged for
// the thighs a seated model of his height draws under the desk, the
// seated model lost to a standing one squeezed to his seated crown (1461
// mm), published up to 203 mm off (39 of 60 pairs more than 50 mm). With
// the desk's end found on the background's own edge and what lies beyond
// it hidden (side_cut.hpp), he is fitted seated and nothing is
// published wrong (docs/cvsm.md, "A desk's side").
TEST(Occlusion, ATallWorkersThighsUnderTheDeskDoNotMakeHimStand) {
  const phantom::PhantomOptions po = ansur_at_desk("seated_flexion", 28048);
  const std::optional<SubjectPosture> posture = chosen_posture(po);
  ASSERT_TRUE(posture);
  EXPECT_EQ(*posture, SubjectPosture::Seated);
  const test::TrustRun run = test::track_for_trust(po, CvsmOptions{}, "seated_flexion at the desk, ansur 28048");
  EXPECT_EQ(run.wrong, 0) << "worst " << run.worst_mm << " mm";
  EXPECT_GE(run.tracking, 36);
}

TEST(Occlusion, BehindADeskTheTrunkTracksWithTheWaistNearTheTruth) {
  const test::TrustRun run = run_at_desk("seated_flexion", "petite", 30);
  // Measured: all 21 pairs after the subject model's 9 init pairs tracked,
  // the waist 19.1 mm off on average (without the edge: never tracked).
  EXPECT_GE(run.tracking, 16);
  EXPECT_LE(run.waist_mean(), 25.0);
}

}  // namespace
}  // namespace spinewatch
