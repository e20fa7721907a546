#pragma once
// Four 32-bit lanes for the fast cost's inner loops: SSE2 on x86-64 and
// NEON on the Pi from the same source, through GCC vector extensions
// (no intrinsics, no run-time dispatch).
#include <cstdint>
#include <cstring>

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
inline f32x4 min(f32x4 a, f32x4 b) { return a < b ? a : b; }
inline f32x4 max(f32x4 a, f32x4 b) { return a > b ? a : b; }
// Rounds toward zero, which is the floor for x ≥ 0.
inline i32x4 trunc(f32x4 x) { return __builtin_convertvector(x, i32x4); }
inline f32x4 to_float(i32x4 x) { return __builtin_convertvector(x, f32x4); }
// The nearest integer, halves up, for |x| < 2^31.
inline i32x4 round(f32x4 x) {
  const f32x4 up = x + splat(0.5f);
  const i32x4 t = trunc(up);
  return t + (to_float(t) > up);  // a true lane is −1: trunc went up, step down
}

}  // namespace spinewatch::lanes
