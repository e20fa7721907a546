#pragma once
// CvsmTracker's private half (the Private-class pattern): the tracker's
// state and its members, declared here and defined by concept:
//   tracker.cpp           the public methods, the per-pair flow (the phase
//                         machine) and the reported result
//   tracker_building.cpp  the subject model's building, provisional postures
//   tracker_search.cpp    the trunk's local and global searches, their
//                         penalties, the twist's sign
//   tracker_limbs.cpp     the articulated limbs' search and auto's arms
//   tracker_refine.cpp    the outline refinement
//   tracker_heading.cpp   the heading followed and probed, the side faced
//   tracker_legs.cpp      what the held-straight legs cannot draw: the step
//                         aside, bent knees, legs unexplained
//   tracker_hidden.cpp    what the views do not show: an occluder, the
//                         pelvis out of the picture
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "cvsm/armless_model.hpp"
#include "cvsm/coordinate_search.hpp"
#include "cvsm/facing_check.hpp"
#include "cvsm/search_params.hpp"
#include "cvsm/silhouette_edges.hpp"
#include "cvsm/subject_estimate.hpp"
#include "cvsm/subject_heading.hpp"
#include "cvsm/xor_cost.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"

namespace spinewatch {

using cvsm_detail::coordinate_descent;
using cvsm_detail::in_range;
using cvsm_detail::kLimbParams;
using cvsm_detail::LimbParams;
using cvsm_detail::PoseParams;
using cvsm_detail::to_limb_params;
using cvsm_detail::to_limbs;
using cvsm_detail::to_params;
using cvsm_detail::to_pose;
using cvsm_detail::without_arms;
using cvsm_detail::without_given_body;

// Where the tracker stands between two pairs. Transitions (track(), no_person()):
//   Building   --a clean pair refines the model; from the
//                 provisional_frames-th on it is published as
//                 tracking (publish_provisional)--> Building
//   Building   --the subject_frames-th clean pair
//                 completes the model-->          Tracking (fit within lost_cost)
//                                                 or Searching (fit beyond it)
//   Building   --no person, or a flagged pair-->  Building (nothing learnt)
//   Searching  --global search, good fit-->       Predicting (clean pair) or Tracking (flagged pair)
//   Tracking,
//   Predicting --local search, good fit-->        Predicting (clean pair) or Tracking (flagged pair)
//   Searching, Tracking,
//   Predicting --fit beyond lost_cost-->          Searching
//   Searching, Tracking,
//   Predicting --no person-->                     Searching
// Nothing leads back to Building but reset().
enum class Phase : std::uint8_t {
  Building,    // the subject model is not complete (init_frames < subject_frames, or none yet): state init,
               // or tracking from provisional_frames on (CvsmResult::provisional)
  Searching,   // the model is built, the pose is not known: the next pair is searched for globally
  Tracking,    // the last fit was good: a local search from it
  Predicting,  // as Tracking, and the pair before was good and clean too: the local search also
               // tries the constant-velocity prediction from `previous`
};

struct CvsmTracker::Impl {
  CameraRig rig;
  CvsmOptions opt;
  CvsmSpec spec;
  SpineSpec spine;
  std::unique_ptr<XorCost> cost;
  int cost_width = 0, cost_height = 0;  // the images `cost` was made for
  std::vector<Eigen::Vector3d> points;

  std::optional<cvsm_detail::SubjectEstimate> subject;  // during init and after
  BodyModel model;
  BodyModel search_model;  // the model the tracked search compares candidates on
  // Articulated limbs: the search model without its arms, which the
  // trunk's own search compares on (the arms' outline, wherever they are,
  // then does not turn the trunk), and which one `evaluate_on` points at.
  BodyModel armless_model;
  const BodyModel* trunk_search_model = &search_model;
  Phase phase = Phase::Building;
  int init_frames = 0;  // pairs built into the model; a model exists once it is 1
  CvsmPose pose, previous;  // `previous`: the pose before `pose`, meaningful in Predicting only
  Eigen::Vector3d home = Eigen::Vector3d::Zero();  // the translation the subject model was built at

  Impl(const CameraRig& r, CvsmOptions o);

  // --- tracker.cpp: the per-pair flow and the reported result
  XorCounts evaluate(const BodyModel& m, const CvsmPose& p, std::int64_t limit);
  // The pose with these trunk parameters and the limbs held where they are.
  // The heading, too, is held: it has a search of its own (follow_heading).
  CvsmPose trunk_pose(const PoseParams& a) const;
  CvsmResult track(const BitMask& frontal, const BitMask& lateral, std::string_view flag);
  CvsmResult finish(TrackingState state, int candidates, std::string_view flag);
  CvsmResult no_person(std::string_view flag);
  // A pair a check withheld (state lost, the fit going on from its pose)
  // was last: the next pair that passes is held too, and only the one
  // after it is published as tracking (docs/cvsm.md, "Reacquired after a
  // withheld stretch").
  void confirm_after_withheld(CvsmResult& r);
  bool withheld_last = false;
  // The pair before was not published as tracking (confirm_after_withheld).
  bool unpublished_last = false;

  // --- tracker_search.cpp: the trunk's searches
  // The hip joints stay where the subject stood or sat: moving them is
  // charged in pixels, so a bend is explained by the spine and pelvis
  // rather than by sliding the whole body (the outline alone barely tells
  // a pelvis tilt from a forward shift). Quadratic, so the few millimetres
  // of sway cost next to nothing and a real step still wins.
  // 0.5 px/mm²: 10 mm cost 50 pixels, 30 mm 450 (a whole-body outline
  // shift of 30 mm leaves well over a thousand XOR pixels). The global
  // search looks everywhere, unanchored; when it finds the subject a real
  // step away (kNewHomeMm), that is where the subject now stands.
  static constexpr double kTranslationPxPerMm2 = 0.5;
  static constexpr double kNewHomeMm = 50;
  bool anchored = true;
  // In the cost's sampled pixels.
  double translation_penalty(const PoseParams& a) const;
  double limb_penalty(const LimbPose& limbs) const;
  std::int64_t cost_of(const PoseParams& a, std::int64_t limit);
  std::int64_t cost_of(const CvsmPose& p, const PoseParams& a, std::int64_t limit);
  // The best of the candidates tried so far, each pruned against it.
  struct Candidates;
  int local_search(int budget);
  std::int64_t searched_cost = INT64_MAX;  // local_search's result's
  int global_search(int budget);
  // Axial twist's sign (check_twist_sign): whether the mirrored twist was
  // scored, and by how much it lost.
  static constexpr std::int64_t kTwistSignMarginPx = 40;
  struct TwistCheck {
    bool checked = false;
    std::int64_t margin_px = 0;  // mirrored twist's cost − the kept one's, ≥ 0
    bool resolved() const { return !checked || margin_px >= kTwistSignMarginPx; }
  };
  TwistCheck check_twist_sign(int& candidates);

  // --- tracker_limbs.cpp: the articulated limbs and auto's arms
  int limb_search(int budget, double step_deg, int levels);
  int joint_refinement(int budget);
  // Auto's arms are searched only where the fixed fit leaves more of the
  // silhouettes unexplained than the subject's own baseline by this
  // (try_arms; the refinement's gate, refine_follows, too). A ratio of the
  // silhouettes' pixels (the reported cost).
  static constexpr double kArmsEvidenceRise = 0.1;
  // Which pair the arms' pass runs on: a tracked one, or a building one
  // (building_arms: searched from a smaller rise, kBuildingCostRise, and
  // held to a stricter bound on the legs, as the pair shapes the model).
  enum class ArmsPass { Tracked, Building };
  bool arms_pass = false;  // the arms' search of the auto mode is running
  bool wide_arms = false;  // ... and it starts from hanging arms
  bool searching_limbs() const;
  // Which of the limbs' parameters the search moves: all of them, or in
  // the auto mode the arms' (the shoulders' two angles and the elbow).
  bool searched_limb(std::size_t i) const;
  template <class LimbCost>
  int place_arms(LimbParams& best, std::int64_t& best_cost, LimbCost& limb_cost);
  void try_arms(CvsmResult& r, TwistCheck& twist, const CvsmPose& before, bool searched_globally, std::string_view flag,
                const BitMask& frontal, const BitMask& lateral, ArmsPass pass = ArmsPass::Tracked);

  // --- tracker_refine.cpp: the outline refinement
  std::array<cvsm_detail::SilhouetteEdges, 2> edges;  // the pair's silhouettes' edges (refine)
  bool refining() const;
  CvsmResult settle(const BitMask& frontal, const BitMask& lateral, int candidates, std::string_view flag,
                    bool searched_globally);
  bool refine_follows(double fixed_cost) const;
  // The search's pose on a pair the refinement moved: the published pose
  // is the refined one, the next pair is searched from this one.
  std::optional<CvsmPose> searched_pose;
  int refine(const BitMask& frontal, const BitMask& lateral, int steps);

  // --- tracker_heading.cpp: the heading and the side faced
  std::int64_t silhouette_px = 0;  // both views of the current pair, whole pixels
  int follow_heading(std::int64_t current_cost);
  int probe_headings();
  int weigh_facing(cvsm_detail::SubjectEstimate& s, bool completes);
  CvsmOptions placing_options() const;
  cvsm_detail::SubjectEstimate fresh_at_allowed_heading(const BitMask& frontal, const BitMask& lateral,
                                                        double heading_deg) const;
  void weigh_reacquired(const BitMask& frontal, const BitMask& lateral, CvsmResult& r);
  void hold_turned_away(const BitMask& frontal, const BitMask& lateral, CvsmResult& r);
  // Whether the views told the subject's front from its back when the
  // heading was last searched (choose_heading while building,
  // probe_headings at reacquisition): until they do, nothing is
  // published as tracking (docs/cvsm.md, "Heading").
  bool heading_resolved = true;
  cvsm_detail::FrontBackEvidence front_back;  // the building pairs' mirror comparisons
  // Where the range does not take the side turned away: the evidence of the
  // side he faces, and whether he is held turned away (nothing tracking).
  cvsm_detail::FacingGuard facing_guard;
  bool held_away = false;
  // Held turned away by the margin the side turned away needs
  // (kAwayPreferenceFraction, summed over the building pairs): the
  // subject is followed and published turned away, as over the full circle.
  bool away_followed = false;
  double on_allowed_side(double heading_deg) const;
  // Whether an early posture may be published as to the side faced: the
  // facing check has decided for the allowed side (over the full circle,
  // heading_resolved says it). Undecided, the model may be its own mirror
  // or barely fit (carrying a box, 25762's side led by under 1 %).
  bool facing_settled() const;
  bool left_view = false;  // no person in view since the last tracked pair

  // --- tracker_building.cpp: the subject model's building
  CvsmResult building_pair(const BitMask& frontal, const BitMask& lateral, std::string_view flag);
  int start_subject(const BitMask& frontal, const BitMask& lateral, const CvsmOptions& options);
  void publish_provisional(CvsmResult& r);
  double best_building_cost = 2;  // the lowest reported cost of the building's pairs
  // How far a building pair's cost may rise above best_building_cost and
  // its posture still be one the model holds: a provisional posture is
  // published within it; the completing pair beyond it is withheld
  // (publish_provisional, withhold_moved_while_building).
  // The building fits shape and pose together, so a posture the
  // model does not hold (a lunge, a raised arm) is partly taken into the
  // shape and the pose follows it less; the cost says so before the
  // posture goes wrong. On the development subject's lunge the fit was
  // 46 mm off at a rise of 0.048 and 51 mm at 0.067, while reaching arms
  // rose to 0.039 at 20 mm (docs/cvsm.md, "Provisional model").
  static constexpr double kBuildingCostRise = 0.04;
  void withhold_moved_while_building(CvsmResult& r);
  // Where the height is the stature (stature_is_height), it is refined on
  // a building pair only while the model built so far fits the pair within
  // kBuildingCostRise of the building's best; beyond, the subject has moved
  // into a posture the model does not hold, and the height would follow it.
  cvsm_detail::ShapeRefinement building_refinement();
  void building_arms(const BitMask& frontal, const BitMask& lateral, std::string_view flag, int& candidates);
  // Both views' silhouette pixels on the pair that completed the model: what
  // a tracked pair's misfit is weighed against where its own outline is
  // smaller (XorCounts::cost_against). 0 while the model is being built.
  std::int64_t built_silhouette_px = 0;
  // A pair was left out of the building (occluded, no one in view) since
  // its first: the model is built from the pairs between, and no early
  // posture is published on it (in a cluttered room, 11953's were 50–56 mm
  // off where the complete model's were as well; docs/cvsm.md, "Provisional
  // model").
  bool building_interrupted = false;

  // --- tracker_legs.cpp: what the held-straight legs cannot draw
  // The trunk upright within this: the step aside is searched, bent knees
  // are judged (follow_step, withhold_bent_knees).
  static constexpr double kStepUprightDeg = 15;
  std::array<BitMask, 2> legs_hidden;
  int follow_step();
  // The share of both silhouettes' pixels the fit at `points` leaves
  // unexplained below the waist's row in each view (lower_residual.hpp):
  // where the two differ, or only the silhouette's pixels the model misses.
  enum class BelowWaist { Xor, SilhouetteOutside };
  double residual_below_waist(const BitMask& frontal, const BitMask& lateral, const CvsmResult& r,
                              BelowWaist what = BelowWaist::Xor);
  std::optional<double> standing_height;  // reset when a subject model is built
  void withhold_bent_knees(CvsmResult& r);
  void withhold_unexplained_legs(const BitMask& frontal, const BitMask& lateral, CvsmResult& r);

  // --- tracker_hidden.cpp: what the views do not show
  // What an occluder in front of the person hides in each view (docs/cvsm.md,
  // "Occluded lower body"): the cost does not count the model there.
  std::array<BitMask, 2> hidden;
  std::array<bool, 2> hiding{};
  // What each view cannot tell from the background (SilhouetteResult::
  // unseen), left out of the cost beside the occluder's pixels; whether
  // the cost leaves anything out in each view.
  std::array<const BitMask*, 2> unseen{};
  // Where each view's outline runs along the scene's own edges
  // (SilhouetteResult::scene_edge): a desk's side found there hides what
  // lies beyond it (side_cut.hpp, docs/cvsm.md "A desk's side").
  std::array<const BitMask*, 2> scene_edges{};
  std::array<bool, 2> cost_hides{};
  // The share of each view's lower outline that ends on unseen pixels,
  // this pair's (unseen_end.hpp); the building pairs' shares; and whether
  // their median says the view does not show where the person rests (a
  // dark seat), held once the model is built.
  std::array<double, 2> end_unseen{};
  std::array<std::vector<double>, 2> building_end_unseen;
  std::array<bool, 2> seat_unseen{};
  void weigh_seat_unseen();
  // An occluder's edge in one view, and in the other one too or a seat
  // it cannot see (seat_unseen): neither view shows the lower body.
  bool lower_body_hidden_in_both() const;
  const BitMask* hidden_in(std::size_t view) const { return cost_hides[view] ? &hidden[view] : nullptr; }
  void find_hidden(const BitMask& frontal, const BitMask& lateral);
  void withhold_hidden_lower_body(CvsmResult& r) const;
  void withhold_unseen_pelvis(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) const;
  bool pelvis_seen(const BitMask& frontal, const BitMask& lateral, const CvsmResult& r) const;
  void withhold_misplaced_head(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) const;
  bool head_placed(const BitMask& frontal, const BitMask& lateral, const CvsmResult& r) const;
};

}  // namespace spinewatch
