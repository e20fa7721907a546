// Prints a digest of the silhouette threshold's bits for 4 000 random rows,
// grey and colour, with and without shadows: builds of the threshold on
// other CPUs (SSE2, the scalar fallback on aarch64, the generic build) must
// print the same line (tests/estimator/silhouette/CMakeLists.txt).
#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

#include "silhouette/threshold_row.hpp"

using namespace spinewatch::silhouette_detail;

int main() {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> byte(0, 255), width(1, 330), near(-40, 40);
  std::uint64_t digest = 1469598103934665603ull;
  auto mix = [&](std::uint64_t v) { digest = (digest ^ v) * 1099511628211ull; };
  std::vector<std::uint8_t> frame(2 * 336), background(336), chroma(336);
  std::vector<std::uint64_t> bits(6);
  for (int n = 0; n < 4000; ++n) {
    const bool colour = n % 2 == 1;
    ThresholdRow row;
    row.width = colour ? (width(rng) & ~1) + 2 : width(rng);
    row.frame_step = colour ? 2 : 1 + n % 3 / 2;
    // Backgrounds and frames near each other, so every branch is taken.
    for (int x = 0; x < row.width; ++x) {
      background[static_cast<std::size_t>(x)] = static_cast<std::uint8_t>(byte(rng));
      chroma[static_cast<std::size_t>(x)] = static_cast<std::uint8_t>(std::clamp(128 + near(rng), 0, 255));
    }
    for (int i = 0; i < 2 * row.width; ++i) {
      const int b = background[static_cast<std::size_t>(i / 2)];
      frame[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(
          std::clamp(i % 2 == 0 || !colour ? b + near(rng) : chroma[static_cast<std::size_t>(i / 2)] + near(rng) / 4, 0, 255));
    }
    row.frame = frame.data();
    row.background = background.data();
    row.gain_q7 = std::uniform_int_distribution<int>(90, 170)(rng);
    row.threshold = std::uniform_int_distribution<int>(4, 40)(rng);
    if (colour) {
      row.chroma_background = chroma.data();
      row.chroma_threshold = std::uniform_int_distribution<int>(2, 20)(rng);
      row.shadow_q7 = std::uniform_int_distribution<int>(40, 128)(rng);
    }
    threshold_row(row, bits.data());
    for (int w = 0; w < (row.width + 63) / 64; ++w) mix(bits[static_cast<std::size_t>(w)]);
    mix(static_cast<std::uint64_t>(row.width));
  }
  std::printf("digest %016llx\n", static_cast<unsigned long long>(digest));
}
