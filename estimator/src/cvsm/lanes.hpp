#pragma once
// Four 32-bit lanes for the fast cost's inner loops: SSE2 on x86-64 and
// NEON on the Pi from the same source, through GCC vector extensions (no
// run-time dispatch). Where GCC does not find the one instruction by
// itself (min, max, lane masks) it is named here, with a generic fallback.
#include <bit>
#include <cstdint>
#include <cstring>

// SPINEWATCH_LANES_GENERIC builds the fallback on any CPU (to test it).
#if defined(SPINEWATCH_LANES_GENERIC)
#define SPINEWATCH_LANES_SSE2 0
#define SPINEWATCH_LANES_NEON 0
#elif defined(__SSE2__)
#define SPINEWATCH_LANES_SSE2 1
#define SPINEWATCH_LANES_NEON 0
#include <emmintrin.h>
#elif defined(__ARM_NEON)
#define SPINEWATCH_LANES_SSE2 0
#define SPINEWATCH_LANES_NEON 1
#include <arm_neon.h>
#else
#define SPINEWATCH_LANES_SSE2 0
#define SPINEWATCH_LANES_NEON 0
#endif

namespace spinewatch::lanes {

using f32x4 = float __attribute__((vector_size(16)));
using i32x4 = std::int32_t __attribute__((vector_size(16)));

inline f32x4 splat(float x) { return f32x4{x, x, x, x}; }
inline f32x4 load(const float* p) {
  f32x4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store(float* p, f32x4 v) { std::memcpy(p, &v, sizeof v); }
#if SPINEWATCH_LANES_SSE2
inline f32x4 min(f32x4 a, f32x4 b) { return _mm_min_ps(a, b); }
inline f32x4 max(f32x4 a, f32x4 b) { return _mm_max_ps(a, b); }
// Bit j: lane j of a comparison is true.
inline unsigned mask_bits(i32x4 m) { return static_cast<unsigned>(_mm_movemask_ps(std::bit_cast<__m128>(m))); }
#else
#if SPINEWATCH_LANES_NEON
inline f32x4 min(f32x4 a, f32x4 b) { return vminq_f32(a, b); }
inline f32x4 max(f32x4 a, f32x4 b) { return vmaxq_f32(a, b); }
#else
inline f32x4 min(f32x4 a, f32x4 b) { return a < b ? a : b; }
inline f32x4 max(f32x4 a, f32x4 b) { return a > b ? a : b; }
#endif
inline unsigned mask_bits(i32x4 m) {
  return (m[0] != 0 ? 1u : 0u) | (m[1] != 0 ? 2u : 0u) | (m[2] != 0 ? 4u : 0u) | (m[3] != 0 ? 8u : 0u);
}
#endif
// Rounds toward zero, which is the floor for x ≥ 0.
inline i32x4 trunc(f32x4 x) { return __builtin_convertvector(x, i32x4); }
inline f32x4 to_float(i32x4 x) { return __builtin_convertvector(x, f32x4); }
// The nearest integer (halves to even, the CPU's own rounding; the
// generic fallback rounds halves up), for |x| < 2^31.
#if SPINEWATCH_LANES_SSE2
inline i32x4 round(f32x4 x) { return std::bit_cast<i32x4>(_mm_cvtps_epi32(x)); }
#elif SPINEWATCH_LANES_NEON
inline i32x4 round(f32x4 x) { return vcvtnq_s32_f32(x); }
#else
inline i32x4 round(f32x4 x) {
  const f32x4 up = x + splat(0.5f);
  const i32x4 t = trunc(up);
  return t + (to_float(t) > up);  // a true lane is −1: trunc went up, step down
}
#endif

}  // namespace spinewatch::lanes
