#pragma once
// Row spans of one CVSM segment, the solid between two adjacent control
// rings, as the fast cost scan-converts it (see segment_scan.cpp).
#include <array>
#include <cstdint>

#include "spinewatch/estimator/cvsm/xor_cost.hpp"

namespace spinewatch {

// A ring reduced to its extreme points (RingExtremes): point k is its
// extreme along kDirection[k], clockwise on screen from the top (v grows
// downwards).
// Sixteen directions at most 26.6° apart: vertex k of a segment's polygon
// is the farther of its two rings' extremes along kDirection[k], vertices
// 0…8 run down the right side, 8…15, 0 back up the left one, and
// direction k + 8 is the opposite of k.
inline constexpr int kDirections = RingExtremes::kCount;
inline constexpr std::array<std::array<int, 2>, kDirections> kDirection{{{0, -1}, {1, -2}, {1, -1}, {2, -1},
                                                                        {1, 0}, {2, 1}, {1, 1}, {1, 2},
                                                                        {0, 1}, {-1, 2}, {-1, 1}, {-2, 1},
                                                                        {-1, 0}, {-2, -1}, {-1, -1}, {-1, -2}}};
struct SpanImage {
  int width = 0, height = 0;
  int row_step = 1;  // a power of two: only rows r with r % row_step == 0 are scanned
};

// Fills x0[r − r0], x1[r − r0] (first and last pixel, clamped to −1…width)
// for the sampled rows r of the solid between rings a and b, and returns
// r0; `rows` receives r1 − r0 + 1 (0 when the solid misses the image).
// x0 and x1 must hold `height` entries.
int scan_segment(const RingExtremes& a, const RingExtremes& b, const SpanImage& image, std::int16_t* x0,
                 std::int16_t* x1, int& rows);

}  // namespace spinewatch
