#pragma once
// The fit's cost, fast path: control points projected once per changed
// control plane to Q8 pixels, each control ring reduced to how far it
// reaches along 16 fixed directions, the solid between two adjacent rings
// scan-converted as the polygon those bound (cut by the chords from one
// ring to the other) straight into packed rows, four rows at a time
// (src/cvsm/segment_scan.cpp), and the exclusive-or against the
// silhouette counted with popcount on the model's rows only (silhouette
// pixels on other rows are counted once, from per-row totals). A
// candidate is abandoned as soon as its partial count exceeds the best so
// far.
//
// Incremental: a candidate usually moves only some control planes (a spine
// angle leaves the pelvis and legs where they were), so each view keeps the
// last world points, projections and per-segment row spans, and only
// planes whose points changed are projected and only segments touching
// them are scan-converted again. The cache is keyed on the points
// themselves, so it is exact whatever model or pose produced them.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "cvsm/fixed_camera.hpp"
#include "cvsm/outline_ends.hpp"
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"
#include "spinewatch/frames/view.hpp"

namespace spinewatch {

struct XorCounts {
  std::array<std::int64_t, 2> xor_px{};         // per view
  std::array<std::int64_t, 2> silhouette_px{};  // per view
  bool pruned = false;  // stopped early: xor_px is a lower bound above the limit
  std::int64_t total() const { return xor_px[0] + xor_px[1]; }
  double cost() const {
    const auto s = silhouette_px[0] + silhouette_px[1];
    return s > 0 ? static_cast<double>(total()) / static_cast<double>(s) : 1.0;
  }
  // The cost against the larger of the pair's silhouettes and `reference_px`
  // (the subject's as the model was built): a view that foreshortens the
  // person (a camera looking down at a trunk bent towards it) halves the
  // outline's area while the misfit along the outline stays, so the share
  // of the pair's own silhouette would rise with no worse fit
  // (docs/cvsm.md, "Measuring along the world's vertical").
  double cost_against(std::int64_t reference_px) const {
    const auto s = std::max(silhouette_px[0] + silhouette_px[1], reference_px);
    return s > 0 ? static_cast<double>(total()) / static_cast<double>(s) : 1.0;
  }
};

// A projected control ring reduced to how far it reaches along 16 fixed
// directions and which of its points reaches farthest
// (cvsm/segment_scan.hpp). Floats, which hold these integers exactly,
// so the scan loads four at a time.
struct RingSupport {
  static constexpr int kCount = 16;
  alignas(16) float key[kCount];
};

// Sampled rows first, first + row step, … (count of them) of one segment.
struct SegmentRows {
  int first = 0, count = 0;
};

class XorCost {
 public:
  XorCost(const CameraRig& rig, int width, int height);

  void set_silhouettes(const BitMask& frontal, const BitMask& lateral);
  // Pixels of each view where the model is not compared (nullptr: none):
  // what an occluder hides (cvsm/occluder_edge.hpp). They must hold no
  // silhouette pixel; the model's pixels there cost nothing. Kept by
  // pointer until set again.
  void set_hidden(const BitMask* frontal, const BitMask* lateral) { hidden_ = {frontal, lateral}; }
  const BitMask* hidden(View view) const { return hidden_[index_of(view)]; }
  // The silhouettes last set (nullptr before).
  const BitMask* silhouette(View view) const { return silhouettes_[index_of(view)]; }
  // Count only every `step`-th row (1: all; rounded down to a power of
  // two). A coarse search compares candidates on a row sample at a
  // fraction of the cost; counts are then in sampled pixels (silhouette_px
  // too, so cost() stays a ratio), and render() leaves the rows in between
  // empty.
  void set_row_step(int step);
  int row_step() const { return row_step_; }
  // The first sampled row at or below row r (r ≥ 0). A mask, not a
  // modulo: an integer division per edge cost a tenth of the evaluation.
  int first_sampled(int r) const { return (r + row_step_ - 1) & ~(row_step_ - 1); }
  // Counts for the model with these world control points; stops early once
  // the total exceeds `limit`.
  XorCounts evaluate(const BodyModel& model, const std::vector<Eigen::Vector3d>& points,
                     std::int64_t limit = INT64_MAX);
  // The outline refinement's view of the model (cvsm/outline_fit.hpp).
  // outline(): both views scan-converted for these points, and the ends of
  // the model's runs on each sampled row appended to `out` (cleared first).
  // scan(): only scan-converted, after which span_end() reads where the
  // span that bounded an end of an earlier outline() ends now: false when
  // its segment no longer spans that row. Both false (and outline() empty)
  // when a point is behind a camera.
  bool outline(const BodyModel& model, const std::vector<Eigen::Vector3d>& points,
               std::vector<cvsm_detail::OutlineEnd>& out);
  bool scan(const BodyModel& model, const std::vector<Eigen::Vector3d>& points);
  bool span_end(const cvsm_detail::OutlineEnd& end, float& x) const;
  // span_end() for each of `ends`, NaN where it is false.
  void span_ends(const std::vector<cvsm_detail::OutlineEnd>& ends, float* x) const;
  // The model's mask in one view (tests, diagnostics, the subject model).
  BitMask render(const BodyModel& model, const std::vector<Eigen::Vector3d>& points, View view);
  // Projected control points of the last render/evaluate, per view (Q8).
  const std::vector<PixelQ8>& projected(View view) const { return projected_[index_of(view)]; }

 private:
  struct ViewCache {
    std::vector<Eigen::Vector3d> world;  // the points the entries below belong to
    std::vector<std::uint8_t> plane_in_front;
    std::vector<std::uint32_t> plane_version;  // renewed whenever a plane's points change
    std::uint32_t version_counter = 0;
    std::vector<RingSupport> support;  // per plane
    std::vector<std::array<std::uint32_t, 4>> segment_planes;  // per segment: planes a, b and their versions
    std::vector<SegmentRows> segment_rows;  // per segment: its first sampled row and how many
    std::vector<std::int32_t> x0, x1;  // per segment span_stride() spans (first, last pixel)
    std::vector<float> left, right;     // the same spans' continuous ends (scan_segment's SpanEnds)
  };
  // Projects and scan-converts view `view` into the cache's spans and, with
  // `fill`, the model's rows into rows_ (the outline refinement reads only
  // the spans); returns false when a point is behind the camera.
  bool rasterize(const BodyModel& model, const std::vector<Eigen::Vector3d>& points, int view, bool fill = true);
  bool project_plane(int view, const Eigen::Vector3d* world, PixelQ8* out) const;
  std::size_t span_stride() const { return static_cast<std::size_t>(height_) + 3; }  // written four rows at a time

  std::array<FixedCamera, 2> cameras_;
  std::array<std::array<float, 12>, 2> pf_{};  // K·[R|t] per view (distortion-free path)
  int width_, height_, words_;
  std::array<const BitMask*, 2> silhouettes_{};
  std::array<const BitMask*, 2> hidden_{};
  void update_prefix();
  int row_step_ = 1;
  std::array<std::vector<std::int64_t>, 2> row_count_;   // silhouette pixels per row
  std::array<std::vector<std::int64_t>, 2> row_prefix_;  // sampled silhouette pixels in rows < y
  std::array<std::vector<PixelQ8>, 2> projected_;
  std::array<ViewCache, 2> cache_;
  cvsm_detail::OutlineEnds outline_;
  std::vector<std::uint64_t> rows_;  // model rows, height × words
  int y_lo_ = 0, y_hi_ = -1;          // rows touched
};

}  // namespace spinewatch
