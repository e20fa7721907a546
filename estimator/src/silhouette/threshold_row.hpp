#pragma once
// The silhouette's per-pixel test, one image row at a time, straight into
// packed bits: a pixel is foreground when |f − gain·b| > threshold, in
// integers as |128·f − g7·b| > 128·threshold with g7 = round(128·gain).
// Every term fits in 16 bits (b·g7 ≤ 255·255), so the SIMD path works on
// eight pixels per register; the scalar path is its reference (the tests
// hold them bit for bit equal) and the fallback on other CPUs.
//
// With colour (a YUYV frame and a background that has chroma), a pixel is
// also foreground when its pair's chroma is not the background's, and a
// darker pixel that keeps the background's chroma is a shadow, not the
// person (threshold_colour.cpp says how, and why in these units).
#include <cstdint>

namespace spinewatch::silhouette_detail {

struct ThresholdRow {
  const std::uint8_t* frame = nullptr;       // first luma byte of the row
  int frame_step = 1;                        // bytes between luma samples (1 grey, 2 YUYV)
  const std::uint8_t* background = nullptr;  // the row of the background, packed
  int width = 0;
  int gain_q7 = 128;    // clamped to 0…255
  int threshold = 28;   // grey levels
  // Colour: the background's chroma row, U and V of each pixel pair
  // interleaved as in YUYV (width bytes); nullptr for luma alone. Needs
  // frame_step 2 (a YUYV row: chroma in the odd bytes) and an even width.
  const std::uint8_t* chroma_background = nullptr;
  int chroma_threshold = 12;  // chroma levels (|ΔU| + |ΔV|, at the background's brightness); a shadow keeps half
  int shadow_q7 = 64;         // round(128 · darkest shadow ratio); 128: no shadow is removed
};

// A shadow is only believed where the background has colour to keep: on a
// grey wall a darker grey is as likely a grey shirt (|U−128| + |V−128|).
inline constexpr int kShadowMinChroma = 6;

// Writes (width + 63) / 64 words; bits past the width are zero.
void threshold_row_reference(const ThresholdRow& row, std::uint64_t* out);
// The fast path where the CPU has one (SSE2), otherwise the reference.
void threshold_row(const ThresholdRow& row, std::uint64_t* out);

int gain_to_q7(double gain);
int ratio_to_q7(double ratio);  // 0…1 → 0…128

// The colour test alone (threshold_colour.cpp), for the dispatch above and tests.
void threshold_colour_reference(const ThresholdRow& row, std::uint64_t* out);
void threshold_colour(const ThresholdRow& row, std::uint64_t* out);

}  // namespace spinewatch::silhouette_detail
