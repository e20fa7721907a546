#include "spinewatch/estimator/cvsm/xor_cost.hpp"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace spinewatch {
namespace {

std::int64_t cross(const PixelQ8& o, const PixelQ8& a, const PixelQ8& b) {
  return static_cast<std::int64_t>(a.u - o.u) * (b.v - o.v) - static_cast<std::int64_t>(a.v - o.v) * (b.u - o.u);
}

bool less_vu(const PixelQ8& a, const PixelQ8& b) { return a.v < b.v || (a.v == b.v && a.u < b.u); }

template <int N>
void insertion_sort(PixelQ8* pts) {
  for (int i = 1; i < N; ++i) {
    const PixelQ8 p = pts[i];
    int j = i - 1;
    while (j >= 0 && less_vu(p, pts[j])) {
      pts[j + 1] = pts[j];
      --j;
    }
    pts[j + 1] = p;
  }
}

// Pixel of a Q8 coordinate: the one whose square [c − ½, c + ½) holds it.
constexpr int round_q8(std::int64_t v) { return static_cast<int>((v + 128) >> 8); }
constexpr int ceil_q8(std::int64_t v) { return static_cast<int>((v + 255) >> 8); }
constexpr int floor_q8(std::int64_t v) { return static_cast<int>(v >> 8); }

// Q8 without a library call: |coordinates| are clamped far outside the
// image first (a point just in front of the camera projects anywhere).
constexpr double kQ8Limit = 1 << 24;
std::int32_t to_q8(double px) {
  const double q = std::clamp(px * 256.0, -kQ8Limit, kQ8Limit);
  return static_cast<std::int32_t>(static_cast<std::int64_t>(q + 0.5 + kQ8Limit) - static_cast<std::int64_t>(kQ8Limit));
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
      for (int j = 0; j < 4; ++j) p_[static_cast<std::size_t>(v)][static_cast<std::size_t>(4 * i + j)] = p(i, j);
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
  step = std::max(1, step);
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
      prefix[y + 1] = prefix[y] + (static_cast<int>(y) % row_step_ == 0 ? counts[y] : 0);
  }
}

// The distortion-free path is K·(R·X + t) in double and one division per
// point (the same arithmetic as CameraModel::project, so no error bound
// beyond the final rounding to 1/256 px); distorted cameras go through
// FixedCamera (CameraModel::project, rounded to Q8).
bool XorCost::project_plane(int view, const Eigen::Vector3d* world, PixelQ8* out) const {
  const FixedCamera& cam = cameras_[static_cast<std::size_t>(view)];
  if (!cam.integer_path()) {
    for (int k = 0; k < kControlPoints; ++k)
      if (!cam.project(world[k], out[k])) return false;
    return true;
  }
  const auto& p = p_[static_cast<std::size_t>(view)];
  for (int k = 0; k < kControlPoints; ++k) {
    const double x = world[k].x(), y = world[k].y(), z = world[k].z();
    const double w = p[8] * x + p[9] * y + p[10] * z + p[11];
    if (w < 1.0) return false;  // behind, or within 1 mm of, the camera plane
    const double inv = 1.0 / w;
    out[k].u = to_q8((p[0] * x + p[1] * y + p[2] * z + p[3]) * inv);
    out[k].v = to_q8((p[4] * x + p[5] * y + p[6] * z + p[7]) * inv);
  }
  return true;
}

// Scan conversion of the convex hull of two rings' extreme points, in the
// way OpenCV's fillPoly (LINE_8 outline + interior) covers pixels: the
// hull's two chains, monotone in v, give per row the outline pixels — for
// a steep edge (|du| ≤ |dv|) the pixel nearest its crossing with the row's
// centre line, for a shallow one the pixels whose centres it passes within
// the row's band — and the row's span runs between the outermost of them.
void XorCost::scan_segment(ViewCache& cache, int segment, const PixelQ8* a, const PixelQ8* b) const {
  constexpr int kN = 2 * kRingExtremes;
  PixelQ8 pts[kN];
  std::merge(a, a + kRingExtremes, b, b + kRingExtremes, pts, less_vu);
  const int r0 = std::max(0, round_q8(pts[0].v)), r1 = std::min(height_ - 1, round_q8(pts[kN - 1].v));
  const auto seg = static_cast<std::size_t>(segment);
  cache.segment_r0[seg] = r0;
  cache.segment_rows[seg] = std::max(0, r1 - r0 + 1);
  if (r0 > r1) return;
  std::int16_t* x0 = cache.x0.data() + seg * static_cast<std::size_t>(height_);  // index: row − r0
  std::int16_t* x1 = cache.x1.data() + seg * static_cast<std::size_t>(height_);
  for (int r = r0; r <= r1; ++r) {
    x0[r - r0] = INT16_MAX;
    x1[r - r0] = INT16_MIN;
  }
  const int step = row_step_;
  auto widen = [&](int r, std::int64_t lo, std::int64_t hi) {
    if (lo > hi) return;  // passes between two pixel centres
    lo = std::clamp<std::int64_t>(lo, -1, width_);
    hi = std::clamp<std::int64_t>(hi, -1, width_);
    if (lo < x0[r - r0]) x0[r - r0] = static_cast<std::int16_t>(lo);
    if (hi > x1[r - r0]) x1[r - r0] = static_cast<std::int16_t>(hi);
  };
  PixelQ8 chain[kN];
  for (int side = 0; side < 2; ++side) {
    // Andrew's monotone chain along v: one side keeps right turns, the other left.
    int k = 0;
    for (int i = 0; i < kN; ++i) {
      while (k >= 2) {
        const std::int64_t c = cross(chain[k - 2], chain[k - 1], pts[i]);
        if (side == 0 ? c > 0 : c < 0) break;
        --k;
      }
      chain[k++] = pts[i];
    }
    for (int e = 0; e + 1 < k; ++e) {
      const PixelQ8 p = chain[e], q = chain[e + 1];
      int ra = std::max(r0, round_q8(p.v));
      const int rb = std::min(r1, round_q8(q.v));
      if (q.v == p.v) {
        if (ra >= r0 && ra <= r1 && ra % step == 0) widen(ra, round_q8(std::min(p.u, q.u)), round_q8(std::max(p.u, q.u)));
        continue;
      }
      ra += (step - ra % step) % step;  // the first sampled row
      const std::int64_t du = q.u - p.u, dv = q.v - p.v;
      // One floating division per edge (an integer one costs several times
      // more); u stays exact to well under 1/256 px over an image.
      const double slope = static_cast<double>(du) / static_cast<double>(dv);
      auto u_at = [&](std::int64_t v) { return p.u + static_cast<std::int64_t>(static_cast<double>(v - p.v) * slope); };
      if (std::abs(du) <= dv) {
        for (int r = ra; r <= rb; r += step) {
          const int x = round_q8(u_at(std::clamp<std::int64_t>(std::int64_t{r} * 256, p.v, q.v)));
          widen(r, x, x);
        }
      } else {
        for (int r = ra; r <= rb; r += step) {
          const std::int64_t va = std::max<std::int64_t>(p.v, std::int64_t{r} * 256 - 128);
          const std::int64_t vb = std::min<std::int64_t>(q.v, std::int64_t{r} * 256 + 128);
          const std::int64_t ua = u_at(va), ub = u_at(vb);
          // Columns whose centres the edge passes in this row; an end at a
          // vertex is drawn at the vertex's own (rounded) pixel.
          std::int64_t lo = ceil_q8(std::min(ua, ub)), hi = floor_q8(std::max(ua, ub));
          if (va == p.v) lo = std::min<std::int64_t>(lo, round_q8(p.u)), hi = std::max<std::int64_t>(hi, round_q8(p.u));
          if (vb == q.v) lo = std::min<std::int64_t>(lo, round_q8(q.u)), hi = std::max<std::int64_t>(hi, round_q8(q.u));
          widen(r, lo, hi);
        }
      }
    }
  }
}

bool XorCost::rasterize(const BodyModel& model, const std::vector<Eigen::Vector3d>& points, int view) {
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
    cache.extremes.resize(planes);
    proj.assign(points.size(), PixelQ8{});
  }
  // Planes whose points moved: project again, reduce to the ring's extremes.
  bool in_front = true;
  for (std::size_t p = 0; p < planes; ++p) {
    const Eigen::Vector3d* w = points.data() + p * kControlPoints;
    Eigen::Vector3d* cached = cache.world.data() + p * kControlPoints;
    if (std::memcmp(static_cast<const void*>(w), static_cast<const void*>(cached), sizeof(Eigen::Vector3d) * kControlPoints) != 0) {
      std::copy_n(w, kControlPoints, cached);
      // Versions come from one counter that never goes back, so a span
      // keyed on (planes, versions) cannot be mistaken for one of another
      // model whose planes happen to share the indices (standing and
      // seated models are compared on the same cost during the init).
      cache.plane_version[p] = ++cache.version_counter;
      PixelQ8* out = proj.data() + p * kControlPoints;
      cache.plane_in_front[p] = project_plane(view, w, out);
      if (cache.plane_in_front[p]) {
        // Extremes along u, v, u+v and u−v: an octagon inside the ring that
        // loses under a pixel on a ring a few pixels across.
        // Branch-free arg-min/max (the compiler turns these into cmovs).
        std::int32_t key[4][kControlPoints];
        for (int k = 0; k < kControlPoints; ++k) {
          key[0][k] = out[k].u;
          key[1][k] = out[k].v;
          key[2][k] = out[k].u + out[k].v;
          key[3][k] = out[k].u - out[k].v;
        }
        int idx[kRingExtremes];
        for (int d = 0; d < 4; ++d) {
          int lo = 0, hi = 0;
          for (int k = 1; k < kControlPoints; ++k) {
            lo = key[d][k] < key[d][lo] ? k : lo;
            hi = key[d][k] > key[d][hi] ? k : hi;
          }
          idx[2 * d] = lo;
          idx[2 * d + 1] = hi;
        }
        auto& ex = cache.extremes[p];
        for (int i = 0; i < kRingExtremes; ++i) ex[static_cast<std::size_t>(i)] = out[idx[i]];
        insertion_sort<kRingExtremes>(ex.data());
      }
    }
    in_front = in_front && cache.plane_in_front[p];
  }
  if (!in_front) return false;

  std::size_t segments = 0;
  for (const auto& chain : model.chains) segments += chain.size() > 0 ? chain.size() - 1 : 0;
  if (cache.segment_planes.size() != segments) {
    cache.segment_planes.assign(segments, {UINT32_MAX, UINT32_MAX, 0, 0});
    cache.segment_r0.assign(segments, 0);
    cache.segment_rows.assign(segments, 0);
    cache.x0.assign(segments * static_cast<std::size_t>(height_), 0);
    cache.x1.assign(segments * static_cast<std::size_t>(height_), 0);
  }
  std::size_t s = 0;
  for (const auto& chain : model.chains)
    for (std::size_t i = 0; i + 1 < chain.size(); ++i, ++s) {
      const int a = chain[i], b = chain[i + 1];
      const auto ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b);
      // Spans are reused only for the same two planes at the same versions.
      const std::array<std::uint32_t, 4> key{static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b),
                                             cache.plane_version[ua], cache.plane_version[ub]};
      if (cache.segment_planes[s] != key) {
        cache.segment_planes[s] = key;
        scan_segment(cache, static_cast<int>(s), cache.extremes[ua].data(), cache.extremes[ub].data());
      }
      const int r0 = cache.segment_r0[s], n = cache.segment_rows[s];
      const std::int16_t* x0 = cache.x0.data() + s * static_cast<std::size_t>(height_);
      const std::int16_t* x1 = cache.x1.data() + s * static_cast<std::size_t>(height_);
      for (int r = (row_step_ - r0 % row_step_) % row_step_; r < n; r += row_step_) {
        const int lo = std::max<int>(0, x0[r]), hi = std::min<int>(width_ - 1, x1[r]);
        if (lo > hi) continue;
        set_bits(rows_.data() + static_cast<std::ptrdiff_t>(r + r0) * words_, lo, hi);
      }
      if (n > 0) {
        y_lo_ = std::min(y_lo_, r0);
        y_hi_ = std::max(y_hi_, r0 + n - 1);
      }
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
    for (int y = y_lo_ + (row_step_ - y_lo_ % row_step_) % row_step_; y <= y_hi_; y += row_step_) {
      const std::uint64_t* m = rows_.data() + static_cast<std::ptrdiff_t>(y) * words_;
      const std::uint64_t* s = sil.row(y);
      for (int w = 0; w < words_; ++w) x += std::popcount(m[w] ^ s[w]);
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

BitMask XorCost::render(const BodyModel& model, const std::vector<Eigen::Vector3d>& points, int view) {
  BitMask out(width_, height_);
  if (!rasterize(model, points, view)) return out;
  for (int y = y_lo_; y <= y_hi_; ++y)
    std::copy_n(rows_.data() + static_cast<std::ptrdiff_t>(y) * words_, words_, out.row(y));
  return out;
}

}  // namespace spinewatch
