#include "cvsm/xor_cost.hpp"

#include "cvsm/lanes.hpp"
#include "cvsm/segment_scan.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <limits>

namespace spinewatch {
namespace {

// XOR pixels of `rows` sampled rows (every `step`-th) of two masks laid
// out alike, stopping once the count exceeds `budget` (the estimator is
// built with hardware popcount on x86-64).
std::int64_t count_xor_rows(const std::uint64_t* model, const std::uint64_t* silhouette, int words, int rows, int step,
                            std::int64_t budget) {
  std::int64_t count = 0;
  const std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(words) * step;
  for (int r = 0; r < rows; ++r, model += stride, silhouette += stride) {
    for (int w = 0; w < words; ++w) count += std::popcount(model[w] ^ silhouette[w]);
    if (count > budget) break;
  }
  return count;
}

// The same, not counting the pixels set in `hidden` (laid out alike).
std::int64_t count_xor_rows_unhidden(const std::uint64_t* model, const std::uint64_t* silhouette, const std::uint64_t* hidden,
                                     int words, int rows, int step, std::int64_t budget) {
  std::int64_t count = 0;
  const std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(words) * step;
  for (int r = 0; r < rows; ++r, model += stride, silhouette += stride, hidden += stride) {
    for (int w = 0; w < words; ++w) count += std::popcount((model[w] ^ silhouette[w]) & ~hidden[w]);
    if (count > budget) break;
  }
  return count;
}

}  // namespace

XorCost::XorCost(const CameraRig& rig, int width, int height)
    : cameras_{FixedCamera(rig.frontal), FixedCamera(rig.lateral)},
      width_(width), height_(height), words_((width + 63) / 64),
      rows_(static_cast<std::size_t>(words_) * static_cast<std::size_t>(height), 0) {
  const CameraModel* cams[2] = {&rig.frontal, &rig.lateral};
  for (int v = 0; v < 2; ++v) {
    Eigen::Matrix<double, 3, 4> rt;
    rt << cams[v]->R, cams[v]->t;
    const Eigen::Matrix<double, 3, 4> p = cams[v]->camera_matrix * rt;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) pf_[static_cast<std::size_t>(v)][static_cast<std::size_t>(4 * i + j)] = static_cast<float>(p(i, j));
  }
}

void XorCost::set_silhouettes(const BitMask& frontal, const BitMask& lateral) {
  silhouettes_ = {&frontal, &lateral};
  for (int v = 0; v < 2; ++v) {
    auto& counts = row_count_[static_cast<std::size_t>(v)];
    counts.resize(static_cast<std::size_t>(height_));
    for (int y = 0; y < height_; ++y) counts[static_cast<std::size_t>(y)] = silhouettes_[static_cast<std::size_t>(v)]->count_row(y);
  }
  update_prefix();
}

void XorCost::set_row_step(int step) {
  step = static_cast<int>(std::bit_floor(static_cast<unsigned>(std::max(1, step))));
  if (step == row_step_) return;
  row_step_ = step;
  // Spans were scanned for the old sample of rows.
  for (auto& cache : cache_) std::fill(cache.segment_planes.begin(), cache.segment_planes.end(), std::array<std::uint32_t, 4>{UINT32_MAX, UINT32_MAX, 0, 0});
  update_prefix();
}

void XorCost::update_prefix() {
  for (int v = 0; v < 2; ++v) {
    const auto& counts = row_count_[static_cast<std::size_t>(v)];
    auto& prefix = row_prefix_[static_cast<std::size_t>(v)];
    prefix.assign(static_cast<std::size_t>(height_) + 1, 0);
    for (std::size_t y = 0; y < counts.size(); ++y)
      prefix[y + 1] = prefix[y] + ((static_cast<int>(y) & (row_step_ - 1)) == 0 ? counts[y] : 0);
  }
}

// The distortion-free path is K·[R|t]·X in float, four points at a time;
// distorted cameras go through FixedCamera (CameraModel::project, rounded
// to Q8).
bool XorCost::project_plane(int view, const Eigen::Vector3d* world, PixelQ8* out) const {
  const FixedCamera& cam = cameras_[static_cast<std::size_t>(view)];
  if (!cam.integer_path()) {
    for (int k = 0; k < kControlPoints; ++k)
      if (!cam.project(world[k], out[k])) return false;
    return true;
  }
  // Float keeps 24 bits: with world points within 3 m of the origin the
  // pixel coordinates come out within 2e-4 px of CameraModel::project
  // before the rounding to Q8 (test XorCost.ProjectsLikeTheCameraModel).
  using namespace lanes;
  const auto& p = pf_[static_cast<std::size_t>(view)];
  i32x4 in_front = i32x4{} == 0;
  for (int g = 0; g < kControlPoints; g += 4) {
    f32x4 x, y, z;
    for (int j = 0; j < 4; ++j) {
      x[j] = static_cast<float>(world[g + j].x());
      y[j] = static_cast<float>(world[g + j].y());
      z[j] = static_cast<float>(world[g + j].z());
    }
    const f32x4 w = splat(p[8]) * x + splat(p[9]) * y + splat(p[10]) * z + splat(p[11]);
    in_front &= w >= splat(1.0f);  // not behind, nor within 1 mm of, the camera plane
    // |coordinates| are clamped far outside the image (a point just in
    // front of the camera projects anywhere).
    const f32x4 scale = splat(256.0f) / max(w, splat(1.0f)), limit = splat(static_cast<float>(kQ8Limit));
    const f32x4 u = (splat(p[0]) * x + splat(p[1]) * y + splat(p[2]) * z + splat(p[3])) * scale;
    const f32x4 v = (splat(p[4]) * x + splat(p[5]) * y + splat(p[6]) * z + splat(p[7])) * scale;
    const i32x4 uq = round(max(min(u, limit), -limit)), vq = round(max(min(v, limit), -limit));
    for (int j = 0; j < 4; ++j) out[g + j] = PixelQ8{uq[j], vq[j]};
  }
  return (in_front[0] & in_front[1] & in_front[2] & in_front[3]) != 0;
}

bool XorCost::rasterize(const BodyModel& model, const std::vector<Eigen::Vector3d>& points, int view, bool fill) {
  if (y_lo_ <= y_hi_)
    std::fill(rows_.begin() + static_cast<std::ptrdiff_t>(y_lo_) * words_,
              rows_.begin() + static_cast<std::ptrdiff_t>(y_hi_ + 1) * words_, 0);
  y_lo_ = height_;
  y_hi_ = -1;
  ViewCache& cache = cache_[static_cast<std::size_t>(view)];
  auto& proj = projected_[static_cast<std::size_t>(view)];
  const std::size_t planes = points.size() / kControlPoints;
  if (cache.world.size() != points.size()) {
    cache.world.assign(points.size(), Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
    cache.plane_in_front.assign(planes, 0);
    cache.plane_version.assign(planes, 0);
    cache.support.resize(planes);
    proj.assign(points.size(), PixelQ8{});
  }
  // Planes whose points moved: project again, reduce the ring to its support.
  // Only the planes the chains use (a thinned model leaves some out).
  bool in_front = true;
  for (std::size_t p = 0; p < planes; ++p) {
    if (!model.in_chain[p]) continue;
    const Eigen::Vector3d* w = points.data() + p * kControlPoints;
    Eigen::Vector3d* cached = cache.world.data() + p * kControlPoints;
    // A moved plane's first point has almost always moved too: the call
    // to compare the rest is then not made.
    if (w[0] != cached[0] ||
        std::memcmp(static_cast<const void*>(w), static_cast<const void*>(cached), sizeof(Eigen::Vector3d) * kControlPoints) != 0) {
      std::copy_n(w, kControlPoints, cached);
      // Versions come from one counter that never goes back, so a span
      // keyed on (planes, versions) cannot be mistaken for one of another
      // model whose planes happen to share the indices (standing and
      // seated models are compared on the same cost during the init).
      cache.plane_version[p] = ++cache.version_counter;
      PixelQ8* out = proj.data() + p * kControlPoints;
      cache.plane_in_front[p] = project_plane(view, w, out);
      if (cache.plane_in_front[p]) {
        ring_support(out, cache.support[p]);
      }
    }
    in_front = in_front && cache.plane_in_front[p];
  }
  if (!in_front) return false;

  std::size_t segments = 0;
  for (const auto& chain : model.chains) segments += chain.size() > 0 ? chain.size() - 1 : 0;
  if (cache.segment_planes.size() != segments) {
    cache.segment_planes.assign(segments, {UINT32_MAX, UINT32_MAX, 0, 0});
    cache.segment_rows.assign(segments, {});
    cache.x0.assign(segments * span_stride(), 0);
    cache.x1.assign(segments * span_stride(), 0);
    cache.left.assign(segments * span_stride(), 0);
    cache.right.assign(segments * span_stride(), 0);
  }
  const SpanImage image{width_, height_, row_step_};
  std::size_t s = 0;
  for (const auto& chain : model.chains)
    for (std::size_t i = 0; i + 1 < chain.size(); ++i, ++s) {
      const int a = chain[i], b = chain[i + 1];
      const auto ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b);
      // Spans are reused only for the same two planes at the same versions.
      const std::array<std::uint32_t, 4> key{static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b),
                                             cache.plane_version[ua], cache.plane_version[ub]};
      const auto& cached = cache.segment_planes[s];
      if (cached[0] != key[0] || cached[1] != key[1] || cached[2] != key[2] || cached[3] != key[3]) {
        cache.segment_planes[s] = key;
        cache.segment_rows[s] = scan_segment({&cache.support[ua], proj.data() + ua * kControlPoints},
                                             {&cache.support[ub], proj.data() + ub * kControlPoints}, image,
                                             cache.x0.data() + s * span_stride(), cache.x1.data() + s * span_stride(),
                                             {cache.left.data() + s * span_stride(), cache.right.data() + s * span_stride()});
      }
      const SegmentRows rows = cache.segment_rows[s];
      if (rows.count == 0 || !fill) continue;  // (its first row may lie far outside the image)
      const std::int32_t* x0 = cache.x0.data() + s * span_stride();
      const std::int32_t* x1 = cache.x1.data() + s * span_stride();
      std::uint64_t* row = rows_.data() + static_cast<std::ptrdiff_t>(rows.first) * words_;
      const std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(words_) * row_step_;
      for (int r = 0;; row += stride) {  // (row never steps past the last row)
        if (x0[r] <= x1[r]) set_bits(row, x0[r], x1[r]);
        if (++r == rows.count) break;
      }
      y_lo_ = std::min(y_lo_, rows.first);
      y_hi_ = std::max(y_hi_, rows.first + (rows.count - 1) * row_step_);
    }
  return true;
}

XorCounts XorCost::evaluate(const BodyModel& model, const std::vector<Eigen::Vector3d>& points, std::int64_t limit) {
  XorCounts counts;
  for (int v = 0; v < 2; ++v) counts.silhouette_px[static_cast<std::size_t>(v)] = row_prefix_[static_cast<std::size_t>(v)].back();
  std::int64_t done = 0;  // exact counts of finished views
  for (int v = 0; v < 2; ++v) {
    const auto& prefix = row_prefix_[static_cast<std::size_t>(v)];
    const BitMask& sil = *silhouettes_[static_cast<std::size_t>(v)];
    if (!rasterize(model, points, v)) {
      counts.xor_px[static_cast<std::size_t>(v)] = prefix.back() + static_cast<std::int64_t>(width_) * height_;
      counts.pruned = true;
      return counts;
    }
    // Silhouette pixels on rows the model does not reach.
    std::int64_t x = y_lo_ <= y_hi_ ? prefix.back() - (prefix[static_cast<std::size_t>(y_hi_) + 1] - prefix[static_cast<std::size_t>(y_lo_)])
                                    : prefix.back();
    const int y0 = first_sampled(y_lo_);
    if (y0 <= y_hi_) {
      const std::ptrdiff_t offset = static_cast<std::ptrdiff_t>(y0) * words_;
      const BitMask* hidden = hidden_[static_cast<std::size_t>(v)];
      if (hidden)
        x += count_xor_rows_unhidden(rows_.data() + offset, sil.row(0) + offset, hidden->row(0) + offset, words_,
                                     (y_hi_ - y0) / row_step_ + 1, row_step_, limit - done - x);
      else
        x += count_xor_rows(rows_.data() + offset, sil.row(0) + offset, words_, (y_hi_ - y0) / row_step_ + 1, row_step_,
                            limit - done - x);
      if (done + x > limit) {
        counts.xor_px[static_cast<std::size_t>(v)] = x;
        counts.pruned = true;
        return counts;
      }
    }
    counts.xor_px[static_cast<std::size_t>(v)] = x;
    done += x;
  }
  return counts;
}

bool XorCost::scan(const BodyModel& model, const std::vector<Eigen::Vector3d>& points) {
  return rasterize(model, points, 0, false) && rasterize(model, points, 1, false);
}

bool XorCost::outline(const BodyModel& model, const std::vector<Eigen::Vector3d>& points,
                      std::vector<cvsm_detail::OutlineEnd>& out) {
  out.clear();
  for (int v = 0; v < 2; ++v) {
    if (!rasterize(model, points, v, false)) {
      out.clear();
      return false;
    }
    const ViewCache& cache = cache_[static_cast<std::size_t>(v)];
    outline_.reset(height_, static_cast<int>(cache.segment_rows.size()));
    for (std::size_t s = 0; s < cache.segment_rows.size(); ++s) {
      const SegmentRows rows = cache.segment_rows[s];
      outline_.add(static_cast<int>(s), rows.first, rows.count, row_step_, cache.left.data() + s * span_stride(),
                   cache.right.data() + s * span_stride());
    }
    outline_.collect(v, out);
  }
  return true;
}

bool XorCost::span_end(const cvsm_detail::OutlineEnd& end, float& x) const {
  const ViewCache& cache = cache_[end.view];
  const auto segment = static_cast<std::size_t>(end.segment);
  if (segment >= cache.segment_rows.size()) return false;
  const SegmentRows rows = cache.segment_rows[segment];
  if (end.row < rows.first) return false;
  const int i = (end.row - rows.first) / row_step_;
  if (i >= rows.count || rows.first + i * row_step_ != end.row) return false;
  const std::size_t k = segment * span_stride() + static_cast<std::size_t>(i);
  if (cache.right[k] < cache.left[k]) return false;
  x = end.right ? cache.right[k] : cache.left[k];
  return true;
}

void XorCost::span_ends(const std::vector<cvsm_detail::OutlineEnd>& ends, float* x) const {
  for (std::size_t i = 0; i < ends.size(); ++i)
    if (!span_end(ends[i], x[i])) x[i] = std::numeric_limits<float>::quiet_NaN();
}

BitMask XorCost::render(const BodyModel& model, const std::vector<Eigen::Vector3d>& points, View view) {
  BitMask out(width_, height_);
  if (!rasterize(model, points, static_cast<int>(index_of(view)))) return out;
  for (int y = y_lo_; y <= y_hi_; ++y)
    std::copy_n(rows_.data() + static_cast<std::ptrdiff_t>(y) * words_, words_, out.row(y));
  return out;
}

}  // namespace spinewatch
