#include "segment_scan.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace spinewatch {
namespace {

// Four float lanes: SSE2 on x86-64, NEON on the Pi, from the same source
// (GCC vector extensions).
using f32x4 = float __attribute__((vector_size(16)));
using i32x4 = std::int32_t __attribute__((vector_size(16)));

f32x4 splat(float x) { return f32x4{x, x, x, x}; }
f32x4 load(const float* p) {
  f32x4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
f32x4 load_float(const std::int32_t* p) {
  i32x4 v;
  std::memcpy(&v, p, sizeof v);
  return __builtin_convertvector(v, f32x4);
}
void store(float* p, f32x4 v) { std::memcpy(p, &v, sizeof v); }
f32x4 min(f32x4 a, f32x4 b) { return a < b ? a : b; }
f32x4 max(f32x4 a, f32x4 b) { return a > b ? a : b; }
// Truncation is the floor for x ≥ 0.
i32x4 trunc(f32x4 x) { return __builtin_convertvector(x, i32x4); }

struct DirectionLanes {
  alignas(16) float du[kDirections], dv[kDirections];
};
constexpr DirectionLanes direction_lanes() {
  DirectionLanes d{};
  for (int k = 0; k < kDirections; ++k) {
    d.du[k] = static_cast<float>(kDirection[static_cast<std::size_t>(k)][0]);
    d.dv[k] = static_cast<float>(kDirection[static_cast<std::size_t>(k)][1]);
  }
  return d;
}
constexpr DirectionLanes kDirectionLanes = direction_lanes();

constexpr float kFar = 1e9f;  // a bound that never binds

}  // namespace

// The polygon is the union of the two rings along each direction (its
// vertices lie on the convex hull of both rings, already in order, so
// there is no hull to build). What it gives up against the exact hull is
// a sliver along a side that runs between two directions, at most
// 1 − cos 13.3° = 2.7 % of the ring's radius deep (eight directions lost
// 7.6 %, and the fit made up for the shrinkage with a subject 76 mm too
// tall; twelve, 40 mm).
//
// It is filled as the pixels whose centres lie inside the polygon grown by
// the diamond |du| + |dv| ≤ ½: that is what cv::fillPoly covers with its
// LINE_8 outline, which takes along a steep edge the pixel nearest its
// crossing with the row's centre line (grown ½ across columns) and along a
// shallow one every pixel whose centre column it crosses within the row's
// band (grown ½ across rows). A convex polygon is the intersection of its
// edges' half-planes, so a row's span is [max over the left edges' lines,
// min over the right edges' lines], with no walking of edges, no per-edge
// branches and four rows per instruction: the edges are set up four at a
// time, the rows then run four at a time against all of them.
//
// Floats hold Q8 coordinates exactly (|u|, |v| < 2^22 anywhere near the
// image), so the choice of vertices is exact; lines are evaluated relative
// to the top row, within 1e-4 px over a segment's rows.
int scan_segment(const RingExtremes& a, const RingExtremes& b, const SpanImage& image, std::int16_t* x0,
                 std::int16_t* x1, int& rows) {
  constexpr float kQ8 = 1.0f / 256.0f;
  alignas(16) float pu[kDirections + 4], pv[kDirections + 4];
  for (int i = 0; i < kDirections; i += 4) {
    const f32x4 au = load_float(a.u + i), av = load_float(a.v + i), bu = load_float(b.u + i), bv = load_float(b.v + i);
    const f32x4 du = load(kDirectionLanes.du + i), dv = load(kDirectionLanes.dv + i);
    const auto take_a = du * au + dv * av >= du * bu + dv * bv;  // ties: ring a, as in the reference order
    store(pu + i, (take_a ? au : bu) * kQ8);
    store(pv + i, (take_a ? av : bv) * kQ8);
  }
  // Rows whose band holds the top and bottom vertices.
  const int r0 = std::max(0, static_cast<int>(std::floor(pv[0] + 0.5f)));
  const int r1 = std::min(image.height - 1, static_cast<int>(std::floor(pv[kDirections / 2] + 0.5f)));
  rows = std::max(0, r1 - r0 + 1);
  if (rows == 0) return r0;
  const float top = static_cast<float>(r0);
  pu[kDirections] = pu[0];
  pv[kDirections] = pv[0];

  // Edge k runs from vertex k to k + 1: 0…7 down the right side (a bound
  // x ≤ c + s·y), 8…15 up the left (x ≥ c + s·y), y in rows below r0.
  // Horizontal and zero-length edges bound nothing across the row; the
  // polygon's top and bottom rows already hold them.
  alignas(16) float c[kDirections], s[kDirections];
  for (int i = 0; i < kDirections; i += 4) {
    const bool right = i < kDirections / 2;
    const f32x4 p_u = load(pu + i), p_v = load(pv + i) - top;
    const f32x4 du = load(pu + i + 1) - p_u, dv = load(pv + i + 1) - top - p_v;
    const auto edge = right ? dv > splat(0) : dv < splat(0);
    const f32x4 slope = du / (edge ? dv : splat(1));
    // The diamond reaches ½ across the edge's columns, or ½ row along a
    // shallow edge, which is |slope|/2 columns.
    const f32x4 reach = splat(0.5f) * max(slope < splat(0) ? -slope : slope, splat(1));
    const f32x4 at_top = p_u - p_v * slope + (right ? reach : -reach);
    store(c + i, edge ? at_top : splat(right ? kFar : -kFar));
    store(s + i, edge ? slope : splat(0));
  }

  // Spans clamped to −1…width, and to the polygon's own left and right
  // extremes grown by ½ (which also bounds a polygon flattened to a
  // horizontal line, whose edges bound nothing).
  const float width = static_cast<float>(image.width);
  const f32x4 right_limit = splat(std::min(width, pu[4] + 0.5f)), left_limit = splat(std::max(-1.0f, pu[12] - 0.5f));
  const float step = static_cast<float>(image.row_step);
  const f32x4 lane_y = f32x4{0, 1, 2, 3} * step;
  const int first = (r0 + image.row_step - 1) & ~(image.row_step - 1);
  for (int r = first; r <= r1; r += 4 * image.row_step) {
    const f32x4 y = splat(static_cast<float>(r - r0)) + lane_y;
    f32x4 right = splat(c[0]) + splat(s[0]) * y;
    f32x4 left = splat(c[8]) + splat(s[8]) * y;
    for (int e = 1; e < kDirections / 2; ++e) {
      right = min(right, splat(c[e]) + splat(s[e]) * y);
      left = max(left, splat(c[e + 8]) + splat(s[e + 8]) * y);
    }
    right = max(min(right, right_limit), splat(-1.0f));
    left = min(max(left, left_limit), splat(width));
    // Pixel centres x with left ≤ x ≤ right: floor(right) = trunc(right + 1) − 1,
    // ceil(left) = W − floor(W − left) for an integer W ≥ left.
    const i32x4 hi = trunc(right + splat(1.0f)) - 1;
    const std::int32_t w = image.width + 1;
    const i32x4 lo = w - trunc(splat(static_cast<float>(w)) - left);
    for (int j = 0; j < 4; ++j) {
      const int row = r + j * image.row_step;
      if (row > r1) break;
      x0[row - r0] = static_cast<std::int16_t>(lo[j]);
      x1[row - r0] = static_cast<std::int16_t>(hi[j]);
    }
  }
  return r0;
}

}  // namespace spinewatch
