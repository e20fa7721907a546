#pragma once
// Folds a TFLite model's float16 weights into float32 constants, in memory.
//
// MediaPipe's BlazePose models store every weight as a FLOAT16 constant
// feeding a DEQUANTIZE operator whose float32 output is the CONV_2D's
// filter. Arm NN 20.08's TfLite parser reads a convolution's filter only
// from a constant buffer, and refuses these models at their first
// convolution ("Buffer #0 has 0 bytes. For tensor: [24,3,3,3]"). The fold
// rewrites the flatbuffer so that each such DEQUANTIZE is gone and its
// consumers read a FLOAT32 constant holding the same values.
//
// The rewrite edits the flatbuffer in place and appends the float32 data at
// its end (flatbuffer offsets point forward, so appended data is reachable
// from anywhere); it reads only the few TFLite schema fields it needs.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace spinewatch::landmarks {

struct FoldReport {
  std::size_t dequantize_folded = 0;  // DEQUANTIZE operators removed
  std::size_t operators_left = 0;     // operators in all subgraphs after the fold
  std::size_t float32_bytes_added = 0;
};

class ModelFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// IEEE 754 binary16 → binary32, subnormals, infinities and NaN included.
float half_to_float(std::uint16_t h);

// Rewrites `model` (a .tflite flatbuffer); throws ModelFormatError on a
// buffer that is not one.
FoldReport fold_float16_weights(std::vector<std::uint8_t>& model);

}  // namespace spinewatch::landmarks
