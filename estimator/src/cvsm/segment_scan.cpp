#include "cvsm/segment_scan.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "cvsm/lanes.hpp"

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
constexpr bool fixed_slopes_are(std::array<float, 7> slopes) {
  for (int k = 1; k < 8; ++k)
    if (kTable.slope[k] != slopes[static_cast<std::size_t>(k - 1)] || kTable.slope[k + 8] != slopes[static_cast<std::size_t>(k - 1)])
      return false;
  return true;
}
static_assert(fixed_slopes_are({2, 1, 0.5f, 0, -0.5f, -1, -2}), "the row loop adds these multiples of y");

constexpr float kFar = 1e9f;  // beyond any key

// A 16-gon of these directions circumscribing a circle has 1.45 % more
// area than the circle (r²·Σ tan(gap/2) over eight gaps of 26.6° and eight
// of 18.4° = 3.187 r² against π r²); its sides pulled in by 0.72 % of the
// radius make it area-neutral. Measured over 8 noise seeds × 9 phantom
// scenarios × 2 subjects with a search budget of 12: 7 neck means past
// 10 mm instead of 9, their average 6.40 mm instead of 6.59; with the
// budget of 16, 3 either way and a lower average (docs/cvsm.md).
constexpr float kSidesIn = 0.0072f;

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

// The sides from one ring to the other on one side of the polygon: one,
// unless the rings cross on screen.
struct Chords {
  float c[kDirections / 2], s[kDirections / 2];
  int count = 0;
};

}  // namespace

// The directions come in opposite pairs, so one pass over the points
// gives eight maxima and eight minima (the opposite directions' maxima).
// Q8 coordinates and their packed keys are integers a float holds
// exactly (below 2^24).
void ring_support(const PixelQ8* ring, RingSupport& out) {
  const f32x4 du0 = load(kTable.du16), du1 = load(kTable.du16 + 4);
  const f32x4 dv0 = load(kTable.dv16), dv1 = load(kTable.dv16 + 4);
  f32x4 hi0 = splat(-kFar), hi1 = hi0, lo0 = splat(kFar), lo1 = lo0;
  auto add = [&](f32x4 u, f32x4 v, int i) {
    const f32x4 k0 = du0 * u + dv0 * v, k1 = du1 * u + dv1 * v;
    const f32x4 first = splat(static_cast<float>(15 - i)), last = splat(static_cast<float>(i));
    hi0 = max(hi0, k0 + first);
    hi1 = max(hi1, k1 + first);
    lo0 = min(lo0, k0 + last);
    lo1 = min(lo1, k1 + last);
  };
  // Two points (u, v, u, v) converted per instruction, then broadcast.
  static_assert(kControlPoints % 2 == 0 && sizeof(PixelQ8) == 8);
  for (int i = 0; i < kControlPoints; i += 2) {
    i32x4 q;
    std::memcpy(&q, ring + i, sizeof q);
    const f32x4 uv = to_float(q);
    add(__builtin_shufflevector(uv, uv, 0, 0, 0, 0), __builtin_shufflevector(uv, uv, 1, 1, 1, 1), i);
    add(__builtin_shufflevector(uv, uv, 2, 2, 2, 2), __builtin_shufflevector(uv, uv, 3, 3, 3, 3), i + 1);
  }
  // Sides in by a fraction of the ring's half-extent along them (whole
  // Q8 units, so the packed index stays), keeping the circumscribed area
  // (below) what the ring's is.
  const f32x4 in0 = to_float(trunc((hi0 - lo0) * splat(kSidesIn / 32))) * splat(16.0f);
  const f32x4 in1 = to_float(trunc((hi1 - lo1) * splat(kSidesIn / 32))) * splat(16.0f);
  hi0 -= in0;
  lo0 += in0;
  hi1 -= in1;
  lo1 += in1;
  store(out.key, hi0);
  store(out.key + 4, hi1);
  store(out.key + 8, -lo0);
  store(out.key + 12, -lo1);
}

// The solid between two rings is filled as the polygon bounded along each
// of the 16 directions by the farther ring, cut by the sides where the
// farther ring changes from one to the other: their union's convex hull,
// with its ring parts circumscribed by fixed-direction sides (at most
// 1/cos 13.3° − 1 = 2.8 % of the ring's radius out, at a corner, before
// ring_support pulls the sides in by 0.72 %) and its
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
SegmentRows scan_segment(Ring a, Ring b, const SpanImage& image, std::int32_t* x0, std::int32_t* x1, SpanEnds ends) {
  alignas(16) float key[kDirections];
  unsigned from_a = 0;  // bit k: ring a reaches farther along direction k
  for (int i = 0; i < kDirections; i += 4) {
    const f32x4 ka = load(a.support->key + i), kb = load(b.support->key + i);
    from_a |= mask_bits(ka >= kb) << i;
    store(key + i, max(ka, kb) + load(kTable.reach + i));
  }
  // Rows whose centres lie within −v ≤ h₀ and v ≤ h₈, sampled.
  const int step = image.row_step;
  // (Keys are integers in 16·Q8: a shift right by 12 is the floor in px.)
  const int r0 = std::max(0, -(static_cast<std::int32_t>(key[0]) >> 12));
  const int r1 = std::min(image.height - 1, static_cast<std::int32_t>(key[8]) >> 12);
  const int first = (r0 + step - 1) & ~(step - 1);
  if (first > r1) return {first, 0};
  const int count = (r1 - first) / step + 1;

  // Lines in rows below `first`: the fixed sides' intercepts move by
  // slope·first, exactly (slopes are multiples of ½). Directions 0 and 8
  // (scale 0) bound rows and come out 0 here, unused.
  alignas(16) float fixed[kDirections];
  for (int i = 0; i < kDirections; i += 4)
    store(fixed + i, load(key + i) * load(kTable.scale + i) + load(kTable.slope + i) * splat(static_cast<float>(first)));
  // The image's edges are folded into the vertical sides (x ≤ width − 1,
  // x ≥ 0); only a bound beyond the far edge is clamped below, for the
  // conversions.
  fixed[4] = std::min(fixed[4], static_cast<float>(image.width - 1));
  fixed[12] = std::max(fixed[12], 0.0f);

  Chords right, left;
  const unsigned changes = from_a ^ ((from_a >> 1) | (from_a << (kDirections - 1)));  // bit k: k and k + 1 differ
  for (unsigned bits = changes & 0xffffu; bits != 0; bits &= bits - 1) {
    const int k = __builtin_ctz(bits), next = (k + 1) % kDirections;
    const Ring& rk = (from_a >> k) & 1u ? a : b;
    const Ring& rn = (from_a >> next) & 1u ? a : b;
    const PixelQ8 p = rk.points[point_of(rk.support->key[k], k)];
    const PixelQ8 q = rn.points[point_of(rn.support->key[next], next)];
    Chords& side = k < 8 ? right : left;
    if (side_line(p, q, k < 8, first, side.c[side.count], side.s[side.count])) ++side.count;
  }

  const float width = static_cast<float>(image.width);
  const f32x4 lane_y = f32x4{0, 1, 2, 3} * static_cast<float>(step);
  const std::int32_t w = image.width + 1;
  // Broadcast once: the fixed sides, then the chords (a line that never
  // binds when there is none). The fixed sides' slopes are 2, 1, ½, 0,
  // −½, −1, −2 on both sides: an add or a subtract of y, 2y or y/2 each.
  constexpr int kLines = 7 + kDirections / 2;
  f32x4 rc[kLines], rs[kLines], lc[kLines], ls[kLines];
  for (int n = 0; n < 7; ++n) rc[n] = splat(fixed[n + 1]), lc[n] = splat(fixed[n + 9]);
  rc[7] = splat(width), rs[7] = splat(0.0f), lc[7] = splat(-1.0f), ls[7] = splat(0.0f);
  for (int n = 0; n < right.count; ++n) rc[7 + n] = splat(right.c[n]), rs[7 + n] = splat(right.s[n]);
  for (int n = 0; n < left.count; ++n) lc[7 + n] = splat(left.c[n]), ls[7 + n] = splat(left.s[n]);
  const int right_lines = 7 + std::max(1, right.count), left_lines = 7 + std::max(1, left.count);
  for (int i = 0; i < count; i += 4) {
    const f32x4 y = splat(static_cast<float>(i * step)) + lane_y, y2 = y + y, yh = y * splat(0.5f);
    f32x4 r = min(min(min(rc[0] + y2, rc[1] + y), min(rc[2] + yh, rc[3])),
                  min(min(rc[4] - yh, rc[5] - y), min(rc[6] - y2, rc[7] + rs[7] * y)));
    f32x4 l = max(max(max(lc[0] + y2, lc[1] + y), max(lc[2] + yh, lc[3])),
                  max(max(lc[4] - yh, lc[5] - y), max(lc[6] - y2, lc[7] + ls[7] * y)));
    for (int n = 8; n < right_lines; ++n) r = min(r, rc[n] + rs[n] * y);
    for (int n = 8; n < left_lines; ++n) l = max(l, lc[n] + ls[n] * y);
    // Pixel centres x with l ≤ x ≤ r within the image: floor(r) =
    // trunc(r + 1) − 1 for r ≥ −1, ceil(l) = W − floor(W − l) for W ≥ l.
    r = max(r, splat(-1.0f));
    l = min(l, splat(width));
    const i32x4 hi = trunc(r + splat(1.0f)) - 1;
    const i32x4 lo = w - trunc(splat(static_cast<float>(w)) - l);
    std::memcpy(x0 + i, &lo, sizeof lo);
    std::memcpy(x1 + i, &hi, sizeof hi);
    if (ends.left != nullptr) {
      store(ends.left + i, l);
      store(ends.right + i, r);
    }
  }
  return {first, count};
}

}  // namespace spinewatch
