#include "segment_scan.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "lanes.hpp"

namespace spinewatch {
namespace {

using namespace lanes;

static_assert(kControlPoints <= 16, "a ring's point index is packed into 4 bits of its keys");
static_assert(kDirection[0][0] == 0 && kDirection[8][0] == 0 && kDirection[4][1] == 0,
              "0 and 8 bound rows, 1…7 and 9…15 columns");

struct DirectionTable {
  // 16·(du, dv) of directions 0…7 (8…15 are their opposites): packed keys.
  alignas(16) float du16[8], dv16[8];
  // Along direction k, du·u + dv·v ≤ h is, for du ≠ 0, u ≤ (du > 0) or
  // ≥ (du < 0) h/du − (dv/du)·v: a line of fixed slope per direction.
  float slope[kDirections], scale[kDirections];  // −dv/du, 1/(16·256·du) from a packed key
  // How far the diamond |du| + |dv| ≤ ½ px reaches along each direction,
  // in packed-key units (16·Q8).
  alignas(16) float reach[kDirections];
};
constexpr DirectionTable direction_table() {
  DirectionTable t{};
  for (int k = 0; k < kDirections; ++k) {
    const int du = kDirection[static_cast<std::size_t>(k)][0], dv = kDirection[static_cast<std::size_t>(k)][1];
    if (k < 8) t.du16[k] = 16.0f * static_cast<float>(du), t.dv16[k] = 16.0f * static_cast<float>(dv);
    t.slope[k] = du == 0 ? 0.0f : -static_cast<float>(dv) / static_cast<float>(du);
    t.scale[k] = du == 0 ? 0.0f : 1.0f / (16.0f * 256.0f * static_cast<float>(du));
    t.reach[k] = 16.0f * 128.0f * static_cast<float>(std::max(du < 0 ? -du : du, dv < 0 ? -dv : dv));
  }
  return t;
}
constexpr DirectionTable kTable = direction_table();

constexpr float kFar = 1e9f;  // beyond any key

// The point of a ring that a packed key names.
int point_of(float key, int direction) {
  const auto k = static_cast<std::int32_t>(key);
  return direction < 8 ? 15 - (k & 15) : -k & 15;
}

// One side of the polygon through two points, grown by the diamond:
// x ≤ c + s·y on the right (p above q), x ≥ c + s·y on the left (p below
// q), y in rows below `top` (so that a shallow side's large slope does
// not cost the intercept its precision). False for a side that bounds no
// columns (horizontal).
bool side_line(PixelQ8 p, PixelQ8 q, bool right, int top, float& c, float& s) {
  const float pu = static_cast<float>(p.u) / 256.0f, pv = static_cast<float>(p.v - top * 256) / 256.0f;
  const float du = static_cast<float>(q.u - p.u) / 256.0f, dv = static_cast<float>(q.v - p.v) / 256.0f;
  if (right ? dv <= 0 : dv >= 0) return false;
  s = du / dv;
  // The diamond reaches ½ across the side's columns, or ½ row along a
  // shallow side, which is |s|/2 columns.
  const float reach = 0.5f * std::max(1.0f, std::abs(s));
  c = pu - pv * s + (right ? reach : -reach);
  return true;
}

}  // namespace

// The directions come in opposite pairs, so one pass over the points
// gives eight maxima and eight minima (the opposite directions' maxima).
// Q8 coordinates and their packed keys are integers a float holds
// exactly (below 2^24).
void ring_support(const PixelQ8* ring, RingSupport& out) {
  const f32x4 du0 = load(kTable.du16), du1 = load(kTable.du16 + 4);
  const f32x4 dv0 = load(kTable.dv16), dv1 = load(kTable.dv16 + 4);
  f32x4 hi0 = splat(-kFar), hi1 = hi0, lo0 = splat(kFar), lo1 = lo0;
  for (int i = 0; i < kControlPoints; ++i) {
    const f32x4 u = splat(static_cast<float>(ring[i].u)), v = splat(static_cast<float>(ring[i].v));
    const f32x4 k0 = du0 * u + dv0 * v, k1 = du1 * u + dv1 * v;
    const f32x4 first = splat(static_cast<float>(15 - i)), last = splat(static_cast<float>(i));
    hi0 = max(hi0, k0 + first);
    hi1 = max(hi1, k1 + first);
    lo0 = min(lo0, k0 + last);
    lo1 = min(lo1, k1 + last);
  }
  store(out.key, hi0);
  store(out.key + 4, hi1);
  store(out.key + 8, -lo0);
  store(out.key + 12, -lo1);
}

// The solid between two rings is filled as the polygon bounded along each
// of the 16 directions by the farther ring, cut by the sides where the
// farther ring changes from one to the other: their union's convex hull,
// with its ring parts circumscribed by fixed-direction sides (at most
// 1/cos 13.3° − 1 = 2.8 % of the ring's radius out, at a corner) and its
// long sides, which run from one ring to the other, as chords between the
// two rings' extreme points (at most 1 − cos 13.3° = 2.7 % of the radius
// in). Fixed directions alone would have cut a long limb segment's sides
// at up to 13° to their true slope; chords alone need every extreme
// point, not just how far each ring reaches.
//
// It is filled as the pixels whose centres lie inside the polygon grown by
// the diamond |du| + |dv| ≤ ½: that is what cv::fillPoly covers with its
// LINE_8 outline, which takes along a steep edge the pixel nearest its
// crossing with the row's centre line (grown ½ across columns) and along a
// shallow one every pixel whose centre column it crosses within the row's
// band (grown ½ across rows). A convex polygon is the intersection of its
// sides' half-planes, so a row's span is [max over the left sides' lines,
// min over the right sides'], with no edges to walk and four rows per
// instruction. The fixed sides are exact but for the packed index (under
// 1/256 px), the chords within 1e-4 px.
int scan_segment(Ring a, Ring b, const SpanImage& image, std::int16_t* x0, std::int16_t* x1, int& rows) {
  alignas(16) float key[kDirections];
  unsigned from_a = 0;  // bit k: ring a reaches farther along direction k
  for (int i = 0; i < kDirections; i += 4) {
    const f32x4 ka = load(a.support->key + i), kb = load(b.support->key + i);
    const i32x4 take_a = ka >= kb;
    for (int j = 0; j < 4; ++j) from_a |= (take_a[j] != 0 ? 1u : 0u) << (i + j);
    store(key + i, max(ka, kb) + load(kTable.reach + i));
  }
  // Rows whose centres lie within −v ≤ h₀ and v ≤ h₈.
  const int r0 = std::max(0, static_cast<int>(std::ceil(-key[0] / (16.0f * 256.0f))));
  const int r1 = std::min(image.height - 1, static_cast<int>(std::floor(key[8] / (16.0f * 256.0f))));
  rows = std::max(0, r1 - r0 + 1);
  if (rows == 0) return r0;

  // Lines 0…6 the fixed right sides (directions 1…7), then the chords;
  // the same for the left (9…15).
  constexpr int kMaxLines = 7 + kDirections / 2;
  float right_c[kMaxLines], right_s[kMaxLines], left_c[kMaxLines], left_s[kMaxLines];
  for (int k = 1; k < 8; ++k) {
    right_c[k - 1] = key[k] * kTable.scale[k], right_s[k - 1] = kTable.slope[k];
    left_c[k - 1] = key[k + 8] * kTable.scale[k + 8], left_s[k - 1] = kTable.slope[k + 8];
  }
  int right_lines = 7, left_lines = 7;
  const unsigned changes = from_a ^ ((from_a >> 1) | (from_a << (kDirections - 1)));  // bit k: k and k + 1 differ
  for (unsigned bits = changes & 0xffffu; bits != 0; bits &= bits - 1) {
    const int k = __builtin_ctz(bits), next = (k + 1) % kDirections;
    const Ring& rk = (from_a >> k) & 1u ? a : b;
    const Ring& rn = (from_a >> next) & 1u ? a : b;
    const PixelQ8 p = rk.points[point_of(rk.support->key[k], k)];
    const PixelQ8 q = rn.points[point_of(rn.support->key[next], next)];
    if (k < 8) {
      if (side_line(p, q, true, r0, right_c[right_lines], right_s[right_lines])) ++right_lines;
    } else {
      if (side_line(p, q, false, r0, left_c[left_lines], left_s[left_lines])) ++left_lines;
    }
  }

  const float width = static_cast<float>(image.width);
  const float step = static_cast<float>(image.row_step);
  const f32x4 lane_y = f32x4{0, 1, 2, 3} * step;
  const int first = (r0 + image.row_step - 1) & ~(image.row_step - 1);
  for (int r = first; r <= r1; r += 4 * image.row_step) {
    const f32x4 y = splat(static_cast<float>(r)) + lane_y, below_top = y - splat(static_cast<float>(r0));
    f32x4 right = splat(width), left = splat(-1.0f);
    for (int l = 0; l < 7; ++l) {
      right = min(right, splat(right_c[l]) + splat(right_s[l]) * y);
      left = max(left, splat(left_c[l]) + splat(left_s[l]) * y);
    }
    for (int l = 7; l < right_lines; ++l) right = min(right, splat(right_c[l]) + splat(right_s[l]) * below_top);
    for (int l = 7; l < left_lines; ++l) left = max(left, splat(left_c[l]) + splat(left_s[l]) * below_top);
    right = max(right, splat(-1.0f));
    left = min(left, splat(width));
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
