#pragma once
// The TFLite schema's (tensorflow/lite/schema/schema.fbs) field slots and
// enum values that the fold and the resize check read, and the model's
// operator codes.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "flatbuffer_view.hpp"

namespace spinewatch::landmarks {
namespace schema {
constexpr int kModelOperatorCodes = 1, kModelSubgraphs = 2, kModelBuffers = 4;
constexpr int kCodeDeprecatedBuiltin = 0, kCodeBuiltin = 3;
constexpr int kSubgraphTensors = 0, kSubgraphOutputs = 2, kSubgraphOperators = 3;
constexpr int kTensorShape = 0, kTensorType = 1, kTensorBuffer = 2;
constexpr int kOperatorOpcode = 0, kOperatorInputs = 1, kOperatorOutputs = 2, kOperatorBuiltinOptions = 4;
constexpr int kBufferData = 0;
constexpr int kResizeHalfPixelCenters = 3;  // ResizeBilinearOptions
constexpr std::int32_t kDequantize = 6, kResizeBilinear = 23;
constexpr std::uint8_t kFloat32 = 0, kFloat16 = 1;
}  // namespace schema

// The builtin operator code of each entry of the model's operator_codes:
// newer files keep it in the int32 field, older ones in the int8.
inline std::vector<std::int32_t> builtin_codes(const FlatbufferView& fb, std::uint32_t model) {
  std::vector<std::int32_t> codes;
  const auto table = fb.field_vector(model, schema::kModelOperatorCodes);
  for (std::uint32_t i = 0; i < table.size; ++i) {
    const std::uint32_t code = fb.vector_table(table, i);
    codes.push_back(std::max<std::int32_t>(
        static_cast<std::int8_t>(fb.field_scalar<std::uint8_t>(code, schema::kCodeDeprecatedBuiltin, 0)),
        fb.field_scalar<std::int32_t>(code, schema::kCodeBuiltin, 0)));
  }
  return codes;
}

}  // namespace spinewatch::landmarks
