#include "cvsm/subject_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "cvsm/coordinate_search.hpp"
#include "cvsm/posture_hidden.hpp"
#include "cvsm/upright_view.hpp"
#include "spinewatch/estimator/anatomy/spine_depth.hpp"
#include "spinewatch/estimator/anatomy/spine_placement.hpp"

namespace spinewatch::cvsm_detail {
namespace {

struct RowExtent {
  int first = -1, last = -1;
};

RowExtent extent(const BitMask& m, int y) {
  RowExtent e;
  const std::uint64_t* row = m.row(y);
  for (int w = 0; w < m.words_per_row(); ++w)
    if (row[w]) {
      if (e.first < 0) e.first = w * 64 + std::countr_zero(row[w]);
      e.last = w * 64 + 63 - std::countl_zero(row[w]);
    }
  return e;
}

int top_row(const BitMask& m) {
  for (int y = 0; y < m.height(); ++y)
    if (extent(m, y).first >= 0) return y;
  return -1;
}

// Median centre column of the rows between fractions a and b of the blob's height.
double centre_column(const BitMask& m, int top, double a, double b) {
  int bottom = top;
  for (int y = top; y < m.height(); ++y)
    if (extent(m, y).first >= 0) bottom = y;
  std::vector<double> centres;
  for (int y = top + static_cast<int>(a * (bottom - top)); y <= top + static_cast<int>(b * (bottom - top)); ++y) {
    const RowExtent e = extent(m, y);
    if (e.first >= 0) centres.push_back(0.5 * (e.first + e.last));
  }
  if (centres.empty()) return m.width() / 2.0;
  std::nth_element(centres.begin(), centres.begin() + static_cast<std::ptrdiff_t>(centres.size() / 2), centres.end());
  return centres[centres.size() / 2];
}

// Where the ray through `pixel` meets the plane n·X = d.
Eigen::Vector3d on_plane(const CameraModel& cam, const Eigen::Vector2d& pixel, const Eigen::Vector3d& n, double d) {
  const Eigen::Vector3d o = cam.centre_in_world();
  const Eigen::Vector3d r = cam.ray_through(pixel);
  const double t = (d - n.dot(o)) / n.dot(r);
  return o + t * r;
}

// Whether the top of the head is in view: its row (of an upright view) is
// not the image's border. A level view's top row is the image's first row;
// a turned one's is wherever its border crosses the head.
bool crown_in_view(const UprightView& view, int top) {
  if (view.level() || top < 0) return top > 0;
  for (int x = 0; x < view.mask().width(); ++x)
    if (view.mask().get(x, top) && view.on_image_border(x, top)) return false;
  return true;
}

constexpr double kCrown = 0.995;  // top of the model's head as a fraction of height (cvsm-generic.toml)

// H, width, depth, shoulder, limb, tx, ty, tz, flexion, lateral, pelvis flexion, crown, twist
// (the subject may already move while its model is built: a pose left out
// here would be absorbed by the shape)
using ShapeParams = std::array<double, 13>;

// Breadths are searched in mm at the reference height (scale × H), so a
// change of height alone keeps every breadth and only stretches lengths:
// height and breadths are then independent directions for the descent.
constexpr double kReferenceHeight = 1750;

// Height moves the whole spine with it, but what the silhouettes pin down
// best is the shoulder line: a taller model lower down fits almost as well
// as a shorter one higher up, a narrow diagonal valley that a coordinate
// descent crawls along. So the vertical translation is searched with T1
// held still: changing the height parameter keeps T1 (and the shoulders)
// in place and moves only what lies below it.
// How far T1 rises per millimetre of height: standing, L5 rises with it
// (it stands on the legs); seated, L5 stays on the seat.
double t1_fraction(const SpineSpec& spine, SubjectPosture posture, bool measured_spine) {
  // Hanging from the crown, T1 does not follow the height (standing) or
  // by 7 % of it (seated, where the height is the stature): held still
  // either way.
  if (measured_spine) return 0;
  const double t1 = neutral_pose(spine, kReferenceHeight)[kNeckIndex].body_center.y() / kReferenceHeight;
  return posture == SubjectPosture::Standing ? t1 : t1 - spine.l5_height_fraction;
}

void apply_params(SubjectEstimate& s, const ShapeParams& p, double t1) {
  s.crown_y = p[11];
  s.shape.height_mm = p[0];
  const double per_height = kReferenceHeight / p[0];
  s.shape.width_scale = p[1] * per_height;
  s.shape.depth_scale = p[2] * per_height;
  s.shape.shoulder_scale = p[3] * per_height;
  s.shape.limb_scale = p[4] * per_height;
  s.pose.translation = {p[5], p[6] - t1 * p[0], p[7]};
  s.pose.flexion = p[8];
  s.pose.lateral = p[9];
  s.pose.pelvis_flexion = p[10];
  s.pose.twist = p[12];
}

ShapeParams params_of(const SubjectEstimate& s, double t1) {
  const double per_height = s.shape.height_mm / kReferenceHeight;
  return {s.shape.height_mm, s.shape.width_scale * per_height, s.shape.depth_scale * per_height,
          s.shape.shoulder_scale * per_height, s.shape.limb_scale * per_height,
          s.pose.translation.x(), s.pose.translation.y() + t1 * s.shape.height_mm, s.pose.translation.z(),
          s.pose.flexion, s.pose.lateral, s.pose.pelvis_flexion, s.crown_y, s.pose.twist};
}

// The measured placement for this estimate: the standing T1 and L5 of
// people of the subject's stature and where L5 hangs from the crown.
// Standing, the crown is the stature; seated, the stature is the height
// the seated search chose.
struct HangingSpine {
  double stature_mm = 0;
  SpinePlacement standing;
  double l5_y = 0;
};
std::optional<HangingSpine> hanging_spine(const SubjectEstimate& s, double crown_lift_mm) {
  if (!s.measured_spine) return std::nullopt;
  const bool standing = s.shape.posture == SubjectPosture::Standing;
  HangingSpine h;
  if (s.given_stature_mm)
    h.stature_mm = *s.given_stature_mm;
  else
    h.stature_mm = standing && s.measured_crown_mm > 0 ? s.measured_crown_mm : s.shape.height_mm;
  h.standing = default_spine_placement().place(h.stature_mm, s.given_c7_mm, s.given_crest_mm);
  // Seated, L5 hangs from the crown by its standing distance below it
  // (the crown as measured: the fitted one trades against the head's shape),
  // raised by `crown_lift_mm`: where the crown would be with the trunk
  // upright.
  const double crown = s.measured_crown_mm > 0 ? s.measured_crown_mm : s.crown_y;
  h.l5_y = standing ? h.standing.l5_mm : crown + crown_lift_mm - (h.stature_mm - h.standing.l5_mm);
  return h;
}

// Seated, with the spine hung from the measured crown: the lift applies.
bool hung_from_measured_crown(const SubjectEstimate& s) {
  return s.measured_spine && s.shape.posture == SubjectPosture::Seated && s.measured_crown_mm > 0;
}

// How far the head's top of `m` in the estimate's pose (its translation
// and heading aside) lies below where it lies upright: the trunk's flexion,
// side bend and the pelvis's tilt lower it, each about its own pivots.
double crown_drop(const BodyModel& m, const SpineSpec& spine, const SubjectEstimate& s) {
  CvsmPose pose = s.pose;
  pose.translation = Eigen::Vector3d::Zero();
  pose.heading = 0;
  const SpinePose posed = pose_vertebrae(m, spine, pose);
  const VertebraPose& upright_t1 = m.neutral[kNeckIndex];
  const VertebraPose& posed_t1 = posed[kNeckIndex];
  // build() puts the neutral model's head top at crown_y less the translation.
  const Eigen::Vector3d head(0, s.crown_y - s.pose.translation.y() - upright_t1.body_center.y(), 0);
  const Eigen::Vector3d posed_top = posed_t1.body_center + posed_t1.q * (upright_t1.q.inverse() * head);
  return upright_t1.body_center.y() + head.y() - posed_top.y();
}

// The spine's depth in front of the back skin by the published rule, for
// the BMI of the given mass and stature, else the BMI the fitted waist
// depth (the template's L3 section, where the outline's waist is) and the
// stature imply (config/spine-depth.toml, docs/anthropometry.md).
void set_spine_depth(BodyShape& shape, const SubjectEstimate& s, const CvsmSpec& spec, double stature_mm) {
  const SpineDepthRule& rule = default_spine_depth();
  constexpr std::size_t kL3 = 14;
  double bmi = 0;
  if (s.given_mass_kg && *s.given_mass_kg > 0 && stature_mm > 0) {
    bmi = *s.given_mass_kg / std::pow(stature_mm / 1000.0, 2);
  } else {
    const double waist_depth = shape.measured_depth_mm[kL3] > 0
                                   ? shape.measured_depth_mm[kL3]
                                   : spec.trunk[kL3].depth * shape.height_mm * shape.depth_scale;
    bmi = rule.bmi_from_outline(waist_depth, stature_mm);
  }
  bmi = std::clamp(bmi, 16.0, 45.0);  // the rule's sources span about 17–45
  for (std::size_t i = 0; i < kVertebraCount; ++i) shape.spine_depth_mm[i] = rule.mean_mm(region_of(i), bmi);
}

}  // namespace

std::int64_t subject_cost(const SubjectEstimate& s, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine,
                          std::vector<Eigen::Vector3d>& points, std::int64_t limit) {
  const BodyModel m = build(s, spec, spine);
  control_points(m, pose_vertebrae(m, spine, s.pose), points, s.pose.limbs, s.pose.heading);
  return cost.evaluate(m, points, limit).total();
}

namespace {
BodyModel build_lifted(const SubjectEstimate& s, const CvsmSpec& spec, const SpineSpec& generic_spine,
                       double crown_lift_mm) {
  Eigen::Vector3d l5 = s.base_l5;
  const std::optional<HangingSpine> hanging = hanging_spine(s, crown_lift_mm);
  const SpineSpec spine = hanging ? placed_spine(generic_spine, s.shape.height_mm, hanging->standing) : generic_spine;
  if (hanging)
    l5.y() = hanging->l5_y;
  else if (s.shape.posture == SubjectPosture::Standing)
    l5.y() = spine.l5_height_fraction * s.shape.height_mm;
  // The head reaches the crown: its scale is what is left between T1 and
  // the crown, so changing the height moves the trunk and legs, not the
  // top of the head (the two are measured separately).
  BodyShape shape = s.shape;
  const double H = shape.height_mm;
  if (hanging) {
    shape.stature_mm = hanging->stature_mm;
    shape.stature_measured = !s.given_stature_mm && s.shape.posture == SubjectPosture::Standing &&
                             s.measured_crown_mm > 0;
    set_spine_depth(shape, s, spec, hanging->stature_mm);
  }
  const double t1 = neutral_pose(spine, H, l5)[kNeckIndex].body_center.y() + s.pose.translation.y();
  const double generic = (kCrown * H) - neutral_pose(spine, H)[kNeckIndex].body_center.y();
  if (s.crown_y > 0 && generic > 0) shape.head_scale = std::clamp((s.crown_y - t1) / generic, 0.6, 1.6);
  return build_body_model(spec, spine, shape, l5);
}
}  // namespace

double crown_lift(const SubjectEstimate& s, const CvsmSpec& spec, const SpineSpec& spine) {
  if (!hung_from_measured_crown(s)) return 0;
  if (s.crown_lift_mm) return *s.crown_lift_mm;
  const double drop = crown_drop(build_lifted(s, spec, spine, 0), spine, s);
  return drop >= kMinCrownLiftMm ? drop : 0;
}

BodyModel build(const SubjectEstimate& s, const CvsmSpec& spec, const SpineSpec& spine) {
  return build_lifted(s, spec, spine, hung_from_measured_crown(s) ? s.crown_lift_mm.value_or(0) : 0);
}

SubjectEstimate initial_subject(const CameraRig& rig, const CvsmSpec& spec, const SpineSpec& spine,
                                const CvsmOptions& options, const BitMask& frontal, const BitMask& lateral) {
  SubjectEstimate s;
  s.shape.height_mm = options.height_mm;
  s.shape.posture = options.posture.value_or(SubjectPosture::Standing);
  // Rows and columns are read with the world's vertical down the columns
  // (upright_view.hpp): in views rolled 25° the image's own rows put the
  // crown 90–120 mm low and the axis up to 60 mm off.
  const UprightView view_f(rig.frontal, frontal), view_l(rig.lateral, lateral);
  const BitMask &upright_f = view_f.mask(), &upright_l = view_l.mask();
  const int top_f = top_row(upright_f), top_l = top_row(upright_l);
  // Subject's vertical axis: frontal columns give z, lateral columns x.
  const double uf = centre_column(upright_f, top_f, 0.25, 0.5);
  const double ul = centre_column(upright_l, top_l, 0.25, 0.5);
  const Eigen::Vector3d pf =
      on_plane(rig.frontal, view_f.to_image({uf, upright_f.height() / 2.0}), Eigen::Vector3d::UnitX(), 0.0);
  const Eigen::Vector3d pl =
      on_plane(rig.lateral, view_l.to_image({ul, upright_l.height() / 2.0}), Eigen::Vector3d::UnitZ(), pf.z());
  // The trunk's centre line is ahead of the spine by (½ − spine fraction) of the depth.
  const auto& l5 = spec.trunk[kWaistIndex];
  const double spine_x = pl.x() - (0.5 - l5.spine_fraction) * l5.depth * s.shape.height_mm;
  // Height from the head's top in each view where it is not cut off.
  std::vector<double> tops;
  if (crown_in_view(view_f, top_f))
    tops.push_back(on_plane(rig.frontal, view_f.to_image({uf, top_f - 0.5}), Eigen::Vector3d::UnitX(), spine_x).y());
  if (crown_in_view(view_l, top_l))
    tops.push_back(on_plane(rig.lateral, view_l.to_image({ul, top_l - 0.5}), Eigen::Vector3d::UnitZ(), pf.z()).y());
  const double top_y = tops.empty() ? 0.0 : (tops.size() == 1 ? tops[0] : 0.5 * (tops[0] + tops[1]));
  s.given_stature_mm = options.stature_mm;
  s.given_c7_mm = options.c7_height_mm;
  s.given_crest_mm = options.iliac_crest_height_mm;
  s.given_mass_kg = options.mass_kg;
  if (s.given_stature_mm)
    s.shape.height_mm = *s.given_stature_mm;
  else if (s.shape.posture == SubjectPosture::Standing && !tops.empty())
    s.shape.height_mm = std::clamp(top_y / kCrown, 1300.0, 2200.0);
  s.base_l5 = {spine_x, spine.l5_height_fraction * s.shape.height_mm, pf.z()};
  if (s.shape.posture == SubjectPosture::Seated && !tops.empty())
    s.base_l5.y() = top_y - (kCrown - spine.l5_height_fraction) * s.shape.height_mm;
  s.crown_y = tops.empty() ? kCrown * s.shape.height_mm : top_y;
  if (!tops.empty()) s.measured_crown_mm = top_y;
  if (tops.empty()) {
    // The head is cut off by the image's border: the crown is above its
    // edge (by about a third of a head, a guess the fit refines).
    const Eigen::Vector2d top_edge = view_f.to_image({uf, std::max(top_f, 0) - 0.5});
    const double edge = on_plane(rig.frontal, top_edge, Eigen::Vector3d::UnitX(), spine_x).y();
    s.crown_y = std::max(s.crown_y, edge + 0.04 * s.shape.height_mm);
  }
  return s;
}

namespace {
// The statures a seated subject's model is tried at.
std::vector<double> seated_heights() {
  std::vector<double> h;
  for (double height = 1450; height <= 1950; height += 50) h.push_back(height);
  return h;
}
}  // namespace

int choose_posture(SubjectEstimate& s, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine,
                   const CvsmOptions& options) {
  if (options.posture) return 0;
  // With the lower body hidden, the two models are compared on what the
  // occluder leaves in view: all it cuts is hidden (posture_hidden.hpp).
  std::optional<CutSpanHidden> cut_hidden;
  if (s.lower_body_hidden) cut_hidden.emplace(cost);
  std::vector<Eigen::Vector3d> points;
  int n = refine_subject(s, cost, spec, spine, 60);
  std::int64_t best = subject_cost(s, cost, spec, spine, points, INT64_MAX);
  auto seated_at = [&](double height) {
    SubjectEstimate seated = s;
    seated.shape.posture = SubjectPosture::Seated;
    seated.shape.height_mm = height;
    seated.base_l5.y() = s.crown_y - (kCrown - spine.l5_height_fraction) * height;
    n += refine_subject(seated, cost, spec, spine, 60);
    return seated;
  };
  // Standing or seated: seated models of the configured height and 12 %
  // either side decide (one height alone let a petite seated subject lose
  // to a standing model squeezed to her sitting height).
  // A given stature is the height: tried alone, and not searched.
  std::optional<SubjectEstimate> best_seated;
  std::int64_t best_seated_cost = INT64_MAX;
  const double guess = s.given_stature_mm.value_or(options.height_mm);
  std::vector<double> heights{guess};
  if (!s.given_stature_mm) heights = {guess, 0.88 * guess, 1.12 * guess};
  if (!s.given_stature_mm && s.lower_body_hidden) heights = seated_heights();
  for (const double height : heights) {
    SubjectEstimate seated = seated_at(height);
    const std::int64_t c = subject_cost(seated, cost, spec, spine, points, INT64_MAX);
    if (c < best_seated_cost) {
      best_seated_cost = c;
      best_seated = seated;
    }
  }
  if (best_seated_cost >= best) return n + 4;
  if (s.given_stature_mm) {
    s = *best_seated;
    return n + 4;
  }
  // Seated, the crown no longer tells the height: the trunk's length
  // (crown to seat) does, so heights are tried, each hanging from the
  // measured crown, and the best refined (≈ 800 cost evaluations, once;
  // with the lower body hidden, already done above).
  if (!s.lower_body_hidden) {
    for (const double height : seated_heights()) {
      SubjectEstimate seated = seated_at(height);
      const std::int64_t c = subject_cost(seated, cost, spec, spine, points, INT64_MAX);
      if (c < best_seated_cost) {
        best_seated_cost = c;
        best_seated = seated;
      }
    }
  }
  n += refine_subject(*best_seated, cost, spec, spine, 60);
  if (subject_cost(*best_seated, cost, spec, spine, points, INT64_MAX) < best) s = *best_seated;
  return n + 9;
}

bool check_given_stature(SubjectEstimate& s) {
  if (!s.given_stature_mm || s.shape.posture != SubjectPosture::Standing || s.measured_crown_mm <= 0) return false;
  // Only a body taller than the given stature contradicts it: one bending,
  // leaning or crouching looks shorter than it is, and the given stature
  // is then what keeps its model right.
  if (s.measured_crown_mm - *s.given_stature_mm <= kStatureMismatchMm) return false;
  s.rejected_stature_mm = s.given_stature_mm;
  s.given_stature_mm.reset();
  // The landmarks were measured on the same person as the stature: not the
  // one in view.
  s.given_c7_mm.reset();
  s.given_crest_mm.reset();
  s.given_mass_kg.reset();
  s.shape.height_mm = std::clamp(s.measured_crown_mm / kCrown, 1300.0, 2200.0);
  return true;
}

CvsmOptions without_given_body(CvsmOptions o) {
  o.stature_mm.reset();
  o.c7_height_mm.reset();
  o.iliac_crest_height_mm.reset();
  o.mass_kg.reset();
  return o;
}

bool stature_is_height(const SubjectEstimate& s) {
  return s.measured_spine && s.shape.posture == SubjectPosture::Standing && !s.given_stature_mm &&
         s.measured_crown_mm <= 0;
}

int refine_subject(SubjectEstimate& s, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine, int budget,
                   ShapeRefinement what) {
  std::vector<Eigen::Vector3d> points;
  SubjectEstimate trial = s;
  const double t1 = t1_fraction(spine, s.shape.posture, s.measured_spine);
  auto eval = [&](const ShapeParams& p, std::int64_t limit) {
    apply_params(trial, p, t1);
    return subject_cost(trial, cost, spec, spine, points, limit);
  };
  const ShapeParams start = params_of(s, t1);
  const std::int64_t c0 = eval(start, INT64_MAX);
  ShapeParams step{16, 0.06, 0.06, 0.06, 0.08, 12, 8, 12, 3, 3, 3, 8, 3};
  // Standing on the floor with the spine placed for the measured stature,
  // the body does not move up or down: a vertical shift would only trade
  // the template's proportions against the person's and carry the spine
  // with it. Seated, the spine hangs from the crown the silhouettes
  // measured (hanging_spine) and is held there for the same reason: left
  // free, the shift put seated spines 20–40 mm low on ANSUR subjects with
  // their stature and landmarks given (docs/anthropometry.md).
  const bool hung_from_crown = s.shape.posture == SubjectPosture::Seated && s.measured_crown_mm > 0;
  if (s.measured_spine && (s.shape.posture == SubjectPosture::Standing || hung_from_crown)) step[6] = 0;
  // A given stature is the model's height, except standing with the
  // measured placement, where the height is the outline's proportions and
  // the stature places the spine (hanging_spine).
  if (s.given_stature_mm && !(s.measured_spine && s.shape.posture == SubjectPosture::Standing)) step[0] = 0;
  if (what == ShapeRefinement::HeightHeld) step[0] = 0;
  auto d = cvsm_detail::coordinate_descent(start, c0, step, 3, budget,
                                           [&](const ShapeParams& p, std::int64_t limit) { return eval(p, limit); });
  apply_params(s, d.params, t1);
  return d.evaluations + 1;
}

}  // namespace spinewatch::cvsm_detail
