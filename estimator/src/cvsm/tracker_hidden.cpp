// What the views do not show (tracker_impl.hpp): an occluder in front of
// the lower body, left out of the cost, a pelvis that neither view shows,
// and a fitted head beyond the picture where the person's is in it,
// withheld from tracking (docs/cvsm.md, "Occluded lower body", "Pelvis out
// of the picture", "Head above the picture").
#include <algorithm>
#include <cstddef>
#include <vector>

#include "cvsm/head_in_view.hpp"
#include "cvsm/occluder_edge.hpp"
#include "cvsm/pelvis_in_view.hpp"
#include "cvsm/side_cut.hpp"
#include "cvsm/tracker_impl.hpp"
#include "cvsm/unseen_end.hpp"
#include "spinewatch/estimator/fit_flags.hpp"

namespace spinewatch {
namespace {

// A view's lower outline ends on unseen pixels over at least this share
// of its columns, the median over the building's pairs: it does not show
// where the person rests (unseen_end.hpp). The building's medians on the
// varied phantom (six test-set adults, docs/cvsm.md "A black chair"): the
// side view of a black seat, typing at a desk, 0.47–0.75 (0.49 for the
// in-process render of chair_phantom_test); the side view with no chair,
// at a desk or not, 0.11–0.24. The front view of a seated person shows
// the thighs' underside on whatever is dark below them (0.16–0.28 with no
// chair, 0.57–0.90 on the black one) and says nothing of the pelvis: the
// rule below also needs an occluder's edge in one view.
constexpr double kSeatUnseenShare = 0.35;

}  // namespace

void CvsmTracker::Impl::find_hidden(const BitMask& frontal, const BitMask& lateral) {
  // The floor under the person: under the waist once a model exists,
  // else under the point the station looks at.
  Eigen::Vector3d under = Eigen::Vector3d::Zero();
  if (init_frames > 0) {
    const Eigen::Vector3d waist = pose_vertebrae(model, spine, pose)[kWaistIndex].body_center;
    under = {waist.x(), 0, waist.z()};
  }
  const BitMask* masks[2] = {&frontal, &lateral};
  const CameraModel* cams[2] = {&rig.frontal, &rig.lateral};
  for (std::size_t v = 0; v < 2; ++v) {
    hiding[v] = false;
    const std::optional<Eigen::Vector2d> floor = cams[v]->project(under);
    if (!floor) continue;
    if (const auto edge = cvsm_detail::find_occluder_edge(*masks[v], floor->y())) {
      cvsm_detail::hidden_below(*edge, *masks[v], hidden[v]);
      hiding[v] = true;
    }
  }
  // Beyond a thing's side the outline runs along (a desk's end cutting
  // the thighs, seen from the side), the view says nothing either
  // (docs/cvsm.md, "A desk's side").
  std::array<bool, 2> side_cut{};
  for (std::size_t v = 0; v < 2; ++v) {
    const BitMask* edges = scene_edges[v];
    if (!edges || edges->empty()) continue;
    for (const cvsm_detail::Side side : {cvsm_detail::Side::Left, cvsm_detail::Side::Right}) {
      const auto cut = cvsm_detail::find_side_cut(*masks[v], *edges, side);
      if (!cut) continue;
      if (!hiding[v] && !side_cut[v]) hidden[v] = BitMask(masks[v]->width(), masks[v]->height());
      cvsm_detail::add_hidden_beyond(*cut, *masks[v], hidden[v]);
      side_cut[v] = true;
    }
  }
  // The pixels a view cannot tell from the background are hidden as the
  // occluder's are: a model drawn there costs nothing (docs/cvsm.md, "A
  // black chair").
  for (std::size_t v = 0; v < 2; ++v) {
    const BitMask* u = unseen[v];
    const bool any = u && u->width() == masks[v]->width() && u->height() == masks[v]->height() && u->count() > 0;
    cost_hides[v] = hiding[v] || side_cut[v] || any;
    // Weighed on the building's pairs only (weigh_seat_unseen).
    end_unseen[v] = any && phase == Phase::Building ? cvsm_detail::share_ending_on_unseen(*masks[v], *u) : 0;
    if (!any) continue;
    if (!hiding[v] && !side_cut[v]) {
      hidden[v] = *u;
      continue;
    }
    for (int y = 0; y < hidden[v].height(); ++y) {
      std::uint64_t* h = hidden[v].row(y);
      const std::uint64_t* from = u->row(y);
      for (int w = 0; w < hidden[v].words_per_row(); ++w) h[w] |= from[w];
    }
  }
  cost->set_hidden(hidden_in(0), hidden_in(1));
}

// The building's pairs say whether each view shows where the person
// rests: a dark seat under dark clothes leaves it unseen (weigh_seat_unseen
// on every building pair; held once the model is built).
void CvsmTracker::Impl::weigh_seat_unseen() {
  for (std::size_t v = 0; v < 2; ++v) {
    std::vector<double>& shares = building_end_unseen[v];
    shares.push_back(end_unseen[v]);
    std::vector<double> sorted = shares;
    const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
    std::nth_element(sorted.begin(), middle, sorted.end());
    seat_unseen[v] = *middle >= kSeatUnseenShare;
  }
}

bool CvsmTracker::Impl::lower_body_hidden_in_both() const {
  return (hiding[0] || hiding[1]) && (hiding[0] || seat_unseen[0]) && (hiding[1] || seat_unseen[1]);
}

// An occluder hides the lower body in one view at least, and in the other
// an occluder too or a seat it cannot see (typing at a desk on a black
// chair): no view sees the legs or the pelvis's lower outline, so the
// waist rests on the model's guess of them (docs/cvsm.md, "Occluded lower
// body", "A black chair"). Not published as tracking; the fit goes on
// from this pose.
void CvsmTracker::Impl::withhold_hidden_lower_body(CvsmResult& r) const {
  if (r.state == TrackingState::Tracking && lower_body_hidden_in_both()) {
    r.state = TrackingState::Lost;
    if (!r.fit.flag) r.fit.flag = std::string(kLowerBodyHiddenFlag);
  }
}

// Neither view shows the pelvis — each ends before it (an edge of the
// image, docs/cvsm.md, "Pelvis out of the picture") or an occluder hides
// it: the waist rests on the model's proportions, not on the views. Not
// published as tracking, as with the occluder alone above.
void CvsmTracker::Impl::withhold_unseen_pelvis(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) const {
  if (r.state != TrackingState::Tracking || pelvis_seen(frontal, lateral, r)) return;
  r.state = TrackingState::Lost;
  if (!r.fit.flag) r.fit.flag = std::string(kLowerBodyHiddenFlag);
}

// Whether one view at least shows the pelvis (neither an occluder nor the
// image's edge hides it there): a provisional posture needs it too.
bool CvsmTracker::Impl::pelvis_seen(const BitMask& frontal, const BitMask& lateral, const CvsmResult& r) const {
  if (!hiding[0] && !cvsm_detail::pelvis_out_of_view(rig.frontal, frontal, model, r.vertebrae)) return true;
  return !hiding[1] && !cvsm_detail::pelvis_out_of_view(rig.lateral, lateral, model, r.vertebrae);
}

// A view shows the person's head inside the picture where the fit put its
// head beyond the edge (docs/cvsm.md, "Head above the picture"): the model
// stands too high, its neck and shoulders in the head's place. Not published
// as tracking; the fit goes on from this pose.
void CvsmTracker::Impl::withhold_misplaced_head(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) const {
  if (r.state != TrackingState::Tracking || head_placed(frontal, lateral, r)) return;
  r.state = TrackingState::Lost;
  if (!r.fit.flag || *r.fit.flag == kTwistUnresolvedFlag) r.fit.flag = std::string(kHeadBeyondImageFlag);
}

// Neither view contradicts the fitted head.
bool CvsmTracker::Impl::head_placed(const BitMask& frontal, const BitMask& lateral, const CvsmResult& r) const {
  const Eigen::Vector3d head = cvsm_detail::model_head_centre(model, r.vertebrae, r.pose.limbs, r.pose.heading);
  return !cvsm_detail::head_beyond_empty_edge(rig.frontal, frontal, head) &&
         !cvsm_detail::head_beyond_empty_edge(rig.lateral, lateral, head);
}

}  // namespace spinewatch
