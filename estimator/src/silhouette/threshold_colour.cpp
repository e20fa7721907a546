// The silhouette's per-pixel test with colour (threshold_row.hpp).
//
// Why these units. Light that dims a surface (a shadow, a cloud, the
// exposure) scales R, G and B alike, so it scales Y and the chroma offsets
// u = U − 128, v = V − 128 by the same factor k. A pixel lit like the
// background but k times as bright therefore has u_f = k·u_b, and with
// k = F/B (its brightness over the background's):
//     e = |u_f·B − u_b·F| + |v_f·B − v_b·F|  ≈ 0,
// whatever k is. e ≤ chroma_threshold·B says "the background's colour,
// dimmed or brightened": no division, and gain and shadow drop out. F and
// B are the pair's luma (YUYV shares one U, V between two pixels) halved,
// so every product fits in 16 bits: |u|·B ≤ 128·127.
//
// Each pixel is then foreground when
//   - its pair's colour is not the background's (e > chroma_threshold·B:
//     a shirt as bright as the wall but blue), or
//   - its luma differs (the luma test of threshold_row.cpp) and it is not
//     a shadow: darker than the background, no darker than shadow_ratio
//     of it, keeping its colour closely (within half chroma_threshold), on
//     a background with colour to keep (kShadowMinChroma).
// Between half and the whole chroma_threshold the colour decides nothing
// and the luma decides: skin against a beige wall is darker and of a
// similar hue, and must not be taken for the wall's shadow.
#include <algorithm>
#include <cstdlib>

#include "silhouette/threshold_row.hpp"

#if defined(__SSE2__) && !defined(SPINEWATCH_LANES_GENERIC)
#include <emmintrin.h>
#endif

namespace spinewatch::silhouette_detail {
namespace {
constexpr int kMinPairLuma = 4;  // a black background still scales chroma by something
}  // namespace

void threshold_colour_reference(const ThresholdRow& row, std::uint64_t* out) {
  const int words = (row.width + 63) / 64;
  std::fill(out, out + words, 0);
  const int limit = 128 * row.threshold;
  const int tolerance = std::clamp(row.chroma_threshold, 0, 255), shadow_q7 = std::clamp(row.shadow_q7, 0, 128);
  for (int x0 = 0; x0 + 1 < row.width; x0 += 2) {
    const std::uint8_t* f = row.frame + 2 * x0;  // Y0 U Y1 V
    const std::uint8_t* b = row.background + x0;
    const std::uint8_t* cb = row.chroma_background + x0;  // U V
    const int F = (f[0] + f[2]) >> 2;
    const int B = std::max((b[0] + b[1]) >> 2, kMinPairLuma);
    const int uf = f[1] - 128, vf = f[3] - 128, ub = cb[0] - 128, vb = cb[1] - 128;
    const int e = std::abs(uf * B - ub * F) + std::abs(vf * B - vb * F);
    const bool other_colour = e > tolerance * B;
    const bool same_colour = e <= (tolerance * B) >> 1;
    const bool colourful = std::abs(ub) + std::abs(vb) >= kShadowMinChroma;
    for (int i = 0; i < 2; ++i) {
      const int a = 128 * f[2 * i];
      const int c = row.gain_q7 * b[i];
      const bool luma_differs = std::abs(a - c) > limit;
      const bool shadow = c > a && shadow_q7 * (c >> 7) <= a && colourful && same_colour;
      if (other_colour || (luma_differs && !shadow)) {
        const int x = x0 + i;
        out[x >> 6] |= std::uint64_t{1} << (x & 63);
      }
    }
  }
}

#if defined(__SSE2__) && !defined(SPINEWATCH_LANES_GENERIC)
namespace {

// Each 16-bit lane with its neighbour's (0↔1, 2↔3, …): the other pixel of
// a pair, or the other chroma component.
inline __m128i swap_pairs(__m128i x) {
  return _mm_shufflehi_epi16(_mm_shufflelo_epi16(x, _MM_SHUFFLE(2, 3, 0, 1)), _MM_SHUFFLE(2, 3, 0, 1));
}
inline __m128i abs16(__m128i x) { return _mm_max_epi16(x, _mm_sub_epi16(_mm_setzero_si128(), x)); }

struct Constants {
  __m128i zero = _mm_setzero_si128();
  __m128i low_bytes = _mm_set1_epi16(0x00FF);
  __m128i c128 = _mm_set1_epi16(128);
  __m128i min_luma = _mm_set1_epi16(kMinPairLuma);
  __m128i min_chroma = _mm_set1_epi16(kShadowMinChroma - 1);
  __m128i gain, limit, tolerance, shadow;
};

// Eight pixels (four pairs): `frame` their 16 YUYV bytes, `bg` eight luma
// lanes, `cbg` eight chroma lanes (U V U V …). 0xFFFF in a lane: foreground.
inline __m128i eight(const std::uint8_t* frame, __m128i bg, __m128i cbg, const Constants& k) {
  const __m128i raw = _mm_loadu_si128(reinterpret_cast<const __m128i*>(frame));
  const __m128i f = _mm_and_si128(raw, k.low_bytes);  // Y of each pixel
  const __m128i cf = _mm_sub_epi16(_mm_srli_epi16(raw, 8), k.c128);
  const __m128i cb = _mm_sub_epi16(cbg, k.c128);
  // The pair's luma, halved, in both of its lanes.
  const __m128i F = _mm_srli_epi16(_mm_add_epi16(f, swap_pairs(f)), 2);
  const __m128i B = _mm_max_epi16(_mm_srli_epi16(_mm_add_epi16(bg, swap_pairs(bg)), 2), k.min_luma);
  const __m128i d = abs16(_mm_sub_epi16(_mm_mullo_epi16(cf, B), _mm_mullo_epi16(cb, F)));
  const __m128i e = _mm_adds_epu16(d, swap_pairs(d));  // |Δu| + |Δv| terms, in both lanes
  const __m128i limit = _mm_mullo_epi16(B, k.tolerance);
  const __m128i other_colour = _mm_xor_si128(_mm_cmpeq_epi16(_mm_subs_epu16(e, limit), k.zero), _mm_set1_epi16(-1));
  const __m128i same_colour = _mm_cmpeq_epi16(_mm_subs_epu16(e, _mm_srli_epi16(limit, 1)), k.zero);
  const __m128i saturation = abs16(cb);
  const __m128i colourful = _mm_cmpgt_epi16(_mm_add_epi16(saturation, swap_pairs(saturation)), k.min_chroma);
  // Luma as in threshold_row.cpp, all unsigned 16-bit.
  const __m128i a = _mm_slli_epi16(f, 7);
  const __m128i c = _mm_mullo_epi16(bg, k.gain);
  const __m128i diff = _mm_or_si128(_mm_subs_epu16(a, c), _mm_subs_epu16(c, a));
  const __m128i luma_same = _mm_cmpeq_epi16(_mm_subs_epu16(diff, k.limit), k.zero);
  const __m128i not_darker = _mm_cmpeq_epi16(_mm_subs_epu16(c, a), k.zero);
  const __m128i not_too_dark =
      _mm_cmpeq_epi16(_mm_subs_epu16(_mm_mullo_epi16(_mm_srli_epi16(c, 7), k.shadow), a), k.zero);
  const __m128i shadow =
      _mm_andnot_si128(not_darker, _mm_and_si128(_mm_and_si128(not_too_dark, colourful), same_colour));
  const __m128i luma_person = _mm_andnot_si128(_mm_or_si128(luma_same, shadow), _mm_set1_epi16(-1));
  return _mm_or_si128(other_colour, luma_person);
}

}  // namespace

void threshold_colour(const ThresholdRow& row, std::uint64_t* out) {
  const int words = (row.width + 63) / 64;
  std::fill(out, out + words, 0);
  Constants k;
  k.gain = _mm_set1_epi16(static_cast<short>(row.gain_q7));
  k.limit = _mm_set1_epi16(static_cast<short>(128 * row.threshold));
  k.tolerance = _mm_set1_epi16(static_cast<short>(std::clamp(row.chroma_threshold, 0, 255)));
  k.shadow = _mm_set1_epi16(static_cast<short>(std::clamp(row.shadow_q7, 0, 128)));
  const int whole = row.width & ~15;
  for (int x = 0; x < whole;) {
    std::uint64_t word = 0;
    const int word_end = std::min(whole, (x & ~63) + 64);
    for (; x < word_end; x += 16) {
      const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row.background + x));
      const __m128i cb = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row.chroma_background + x));
      const __m128i lo = eight(row.frame + 2 * x, _mm_unpacklo_epi8(b, k.zero), _mm_unpacklo_epi8(cb, k.zero), k);
      const __m128i hi =
          eight(row.frame + 2 * x + 16, _mm_unpackhi_epi8(b, k.zero), _mm_unpackhi_epi8(cb, k.zero), k);
      const unsigned bits = static_cast<unsigned>(_mm_movemask_epi8(_mm_packs_epi16(lo, hi))) & 0xFFFFu;
      word |= std::uint64_t{bits} << (x & 63);
    }
    out[(x - 1) >> 6] = word;
  }
  if (whole < row.width) {
    ThresholdRow tail = row;
    tail.frame = row.frame + 2 * static_cast<std::ptrdiff_t>(whole);
    tail.background = row.background + whole;
    tail.chroma_background = row.chroma_background + whole;
    tail.width = row.width - whole;
    std::uint64_t bits = 0;
    threshold_colour_reference(tail, &bits);
    out[whole >> 6] |= bits << (whole & 63);
  }
}
#else
void threshold_colour(const ThresholdRow& row, std::uint64_t* out) { threshold_colour_reference(row, out); }
#endif

}  // namespace spinewatch::silhouette_detail
