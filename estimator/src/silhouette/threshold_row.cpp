#include "silhouette/threshold_row.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__SSE2__) && !defined(SPINEWATCH_LANES_GENERIC)
#include <emmintrin.h>
#endif

namespace spinewatch::silhouette_detail {

int gain_to_q7(double gain) { return static_cast<int>(std::clamp(std::lround(gain * 128.0), 0L, 255L)); }
int ratio_to_q7(double ratio) { return static_cast<int>(std::clamp(std::lround(ratio * 128.0), 0L, 128L)); }

namespace {
bool colour(const ThresholdRow& row) { return row.chroma_background != nullptr && row.frame_step == 2; }
}  // namespace

void threshold_row_reference(const ThresholdRow& row, std::uint64_t* out) {
  if (colour(row)) return threshold_colour_reference(row, out);
  const int words = (row.width + 63) / 64;
  std::fill(out, out + words, 0);
  const int limit = 128 * row.threshold;
  for (int x = 0; x < row.width; ++x) {
    const int d = 128 * row.frame[x * row.frame_step] - row.gain_q7 * row.background[x];
    if (std::abs(d) > limit) out[x >> 6] |= std::uint64_t{1} << (x & 63);
  }
}

#if defined(__SSE2__) && !defined(SPINEWATCH_LANES_GENERIC)
namespace {

// Sixteen pixels at x (eight per half) to sixteen bits. |a − b| as the OR of
// both saturated differences; "> limit" as "saturated minus limit ≠ 0".
inline unsigned sixteen(__m128i f_lo, __m128i f_hi, const std::uint8_t* bg, __m128i gain, __m128i limit) {
  const __m128i zero = _mm_setzero_si128();
  const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bg));
  auto half = [&](__m128i f, __m128i b16) {
    const __m128i a = _mm_slli_epi16(f, 7);
    const __m128i c = _mm_mullo_epi16(b16, gain);
    const __m128i diff = _mm_or_si128(_mm_subs_epu16(a, c), _mm_subs_epu16(c, a));
    return _mm_cmpeq_epi16(_mm_subs_epu16(diff, limit), zero);  // 0xFFFF: background
  };
  const __m128i lo = half(f_lo, _mm_unpacklo_epi8(b, zero));
  const __m128i hi = half(f_hi, _mm_unpackhi_epi8(b, zero));
  return ~static_cast<unsigned>(_mm_movemask_epi8(_mm_packs_epi16(lo, hi))) & 0xFFFFu;
}

}  // namespace

void threshold_row(const ThresholdRow& row, std::uint64_t* out) {
  if (colour(row)) return threshold_colour(row, out);
  if (row.frame_step != 1 && row.frame_step != 2) return threshold_row_reference(row, out);
  const int words = (row.width + 63) / 64;
  std::fill(out, out + words, 0);
  const __m128i gain = _mm_set1_epi16(static_cast<short>(row.gain_q7));
  const __m128i limit = _mm_set1_epi16(static_cast<short>(128 * row.threshold));
  const __m128i zero = _mm_setzero_si128(), low_bytes = _mm_set1_epi16(0x00FF);
  auto load = [&](int x, __m128i& f_lo, __m128i& f_hi) {
    if (row.frame_step == 1) {
      const __m128i f = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row.frame + x));
      f_lo = _mm_unpacklo_epi8(f, zero);
      f_hi = _mm_unpackhi_epi8(f, zero);
    } else {  // YUYV: luma in the low byte of every 16-bit pair
      const std::uint8_t* p = row.frame + 2 * x;
      f_lo = _mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)), low_bytes);
      f_hi = _mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 16)), low_bytes);
    }
  };
  const int whole = row.width & ~15;
  for (int x = 0; x < whole;) {
    // A word at a time, so each is stored once.
    std::uint64_t word = 0;
    const int word_end = std::min(whole, (x & ~63) + 64);
    for (; x < word_end; x += 16) {
      __m128i f_lo, f_hi;
      load(x, f_lo, f_hi);
      word |= std::uint64_t{sixteen(f_lo, f_hi, row.background + x, gain, limit)} << (x & 63);
    }
    out[(x - 1) >> 6] = word;
  }
  if (whole < row.width) {
    // The last few pixels, through the reference on a shifted row.
    ThresholdRow tail = row;
    tail.frame = row.frame + static_cast<std::ptrdiff_t>(whole) * row.frame_step;
    tail.background = row.background + whole;
    tail.width = row.width - whole;
    std::uint64_t bits = 0;
    threshold_row_reference(tail, &bits);  // fewer than 16 pixels: one word
    out[whole >> 6] |= bits << (whole & 63);
  }
}
#else
void threshold_row(const ThresholdRow& row, std::uint64_t* out) {
  if (colour(row)) return threshold_colour(row, out);
  threshold_row_reference(row, out);
}
#endif

}  // namespace spinewatch::silhouette_detail
