#pragma once
// Control rings reduced to their reach along fixed directions, and the row
// spans of one CVSM segment, the solid between two adjacent rings, as the
// fast cost scan-converts it (src/cvsm/segment_scan.cpp). A detail of
// XorCost, public for its tests.
#include <array>
#include <cstdint>

#include "cvsm/fixed_camera.hpp"
#include "cvsm/xor_cost.hpp"

namespace spinewatch {

// Sixteen directions, clockwise on screen from the top (v grows
// downwards), at most 26.6° apart; direction k + 8 is the opposite of k.
inline constexpr int kDirections = RingSupport::kCount;
inline constexpr std::array<std::array<int, 2>, kDirections> kDirection{{{0, -1}, {1, -2}, {1, -1}, {2, -1},
                                                                        {1, 0}, {2, 1}, {1, 1}, {1, 2},
                                                                        {0, 1}, {-1, 2}, {-1, 1}, {-2, 1},
                                                                        {-1, 0}, {-2, -1}, {-1, -1}, {-1, -2}}};

// A ring's support along kDirection[k] = (du, dv) is h = max over its
// points of du·u + dv·v (Q8). key[k] packs it with the point that reaches
// it, the lowest index i on ties, so that the larger key is the farther
// ring: 16·h + (15 − i) for k < 8, 16·h − i for k ≥ 8. Exact while the
// ring lies within ±1024 px of the image.
void ring_support(const PixelQ8* ring, RingSupport& out);

struct SpanImage {
  int width = 0, height = 0;
  int row_step = 1;  // a power of two: only rows r with r % row_step == 0 are scanned
};

struct Ring {
  const RingSupport* support;
  const PixelQ8* points;  // kControlPoints of them
};

// Spans of the solid between rings a and b on its sampled rows: x0[i] and
// x1[i], the first and last pixel of row first + i·row_step, within
// 0…width − 1 (x0 > x1: the row misses the image). Written four rows at
// a time: x0 and x1 must hold height + 3 entries. With `ends`, also the
// spans' continuous ends, of which x0 and x1 are the first and last pixel
// centre inside: ends.left[i] ≤ x ≤ ends.right[i], the image's edges
// folded in (a span reaching past one ends at its last pixel's centre);
// the same size.
struct SpanEnds {
  float* left;
  float* right;
};
SegmentRows scan_segment(Ring a, Ring b, const SpanImage& image, std::int32_t* x0, std::int32_t* x1,
                         SpanEnds ends = {nullptr, nullptr});

}  // namespace spinewatch
