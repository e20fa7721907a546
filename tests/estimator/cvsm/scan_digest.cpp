// Prints a digest of the ring supports and segment spans the fast cost
// draws for 20 000 random pairs of elliptic rings, in and around the
// image, every row and every 4th: builds of the scan on other lanes
// (SSE2, NEON, the generic fallback) must print the same line.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>
#include "cvsm/segment_scan.hpp"
using namespace spinewatch;
int main() {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> c(-40 * 256, 360 * 256), r(0, 60 * 256);
  std::uint64_t digest = 1469598103934665603ull;
  auto mix = [&](std::int64_t v) { digest = (digest ^ static_cast<std::uint64_t>(v)) * 1099511628211ull; };
  std::vector<std::int32_t> x0(243), x1(243);
  int rows = 0;
  for (int n = 0; n < 20000; ++n) {
    PixelQ8 a[kControlPoints], b[kControlPoints];
    const int ua = c(rng), va = c(rng) * 3 / 4, ub = ua + r(rng) - 30 * 256, vb = va + r(rng);
    const int ra = r(rng) / 2, rb = r(rng) / 2, fa = r(rng) / 4, fb = r(rng) / 4;
    for (int k = 0; k < kControlPoints; ++k) {
      const double t = k * 3.14159265358979 / 6;
      a[k] = {ua + static_cast<int>(ra * std::cos(t)), va + static_cast<int>(fa * std::sin(t))};
      b[k] = {ub + static_cast<int>(rb * std::cos(t)), vb + static_cast<int>(fb * std::sin(t))};
    }
    RingSupport sa, sb;
    ring_support(a, sa);
    ring_support(b, sb);
    for (float k : sa.key) mix(static_cast<std::int64_t>(k));
    const SegmentRows s = scan_segment({&sa, a}, {&sb, b}, SpanImage{320, 240, n % 3 == 0 ? 4 : 1}, x0.data(), x1.data());
    mix(s.first);
    mix(s.count);
    rows += s.count;
    for (int i = 0; i < s.count; ++i) mix(x0[static_cast<std::size_t>(i)] <= x1[static_cast<std::size_t>(i)] ? (x0[static_cast<std::size_t>(i)] * 1000 + x1[static_cast<std::size_t>(i)]) : -1);
  }
  std::printf("rows %d digest %016llx\n", rows, static_cast<unsigned long long>(digest));
}
