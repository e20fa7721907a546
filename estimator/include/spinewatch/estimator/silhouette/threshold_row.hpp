#pragma once
// The silhouette's per-pixel test, one image row at a time, straight into
// packed bits: a pixel is foreground when |f − gain·b| > threshold, in
// integers as |128·f − g7·b| > 128·threshold with g7 = round(128·gain).
// Every term fits in 16 bits (b·g7 ≤ 255·255), so the SIMD path works on
// eight pixels per register; the scalar path is its reference (the tests
// hold them bit for bit equal) and the fallback on other CPUs.
#include <cstdint>

namespace spinewatch::silhouette_detail {

struct ThresholdRow {
  const std::uint8_t* frame = nullptr;       // first luma byte of the row
  int frame_step = 1;                        // bytes between luma samples (1 grey, 2 YUYV)
  const std::uint8_t* background = nullptr;  // the row of the background, packed
  int width = 0;
  int gain_q7 = 128;    // clamped to 0…255
  int threshold = 28;   // grey levels
};

// Writes (width + 63) / 64 words; bits past the width are zero.
void threshold_row_reference(const ThresholdRow& row, std::uint64_t* out);
// The fast path where the CPU has one (SSE2), otherwise the reference.
void threshold_row(const ThresholdRow& row, std::uint64_t* out);

int gain_to_q7(double gain);

}  // namespace spinewatch::silhouette_detail
