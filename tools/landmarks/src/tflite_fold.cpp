#include "spinewatch/landmarks/tflite_fold.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <map>
#include <string>

#include "flatbuffer_view.hpp"
#include "tflite_schema.hpp"

namespace spinewatch::landmarks {
namespace {

using schema::kDequantize;
using schema::kFloat16;
using schema::kFloat32;

std::size_t element_count(const FlatbufferView& fb, std::uint32_t tensor) {
  const auto shape = fb.field_vector(tensor, schema::kTensorShape);
  std::size_t n = 1;
  for (std::uint32_t i = 0; i < shape.size; ++i) n *= static_cast<std::size_t>(fb.vector_scalar<std::int32_t>(shape, i));
  return n;
}

// Appends a [ubyte] vector holding `values` as float32, its data 16-byte
// aligned; returns the position of its length word.
std::uint32_t append_float32_vector(std::vector<std::uint8_t>& bytes, const std::vector<float>& values) {
  while ((bytes.size() + 4) % 16 != 0) bytes.push_back(0);
  const auto at = static_cast<std::uint32_t>(bytes.size());
  const auto length = static_cast<std::uint32_t>(values.size() * sizeof(float));
  bytes.resize(bytes.size() + 4 + length);
  std::memcpy(bytes.data() + at, &length, 4);
  std::memcpy(bytes.data() + at + 4, values.data(), length);
  return at;
}

class SubgraphFolder {
 public:
  SubgraphFolder(std::vector<std::uint8_t>& bytes, std::uint32_t model, std::uint32_t subgraph,
                 const std::vector<bool>& is_dequantize)
      : bytes_(bytes), model_(model), subgraph_(subgraph), is_dequantize_(is_dequantize) {}

  void fold(FoldReport& report) {
    const FlatbufferView fb(bytes_);
    const auto operators = fb.field_vector(subgraph_, schema::kSubgraphOperators);
    std::vector<bool> remove(operators.size, false);
    for (std::uint32_t i = 0; i < operators.size; ++i) {
      remove[i] = try_fold(fb.vector_table(operators, i), report);
    }
    rewire_inputs();
    report.operators_left += compact_operators(remove);
  }

 private:
  // Folds one operator if it is a DEQUANTIZE of a FLOAT16 constant.
  bool try_fold(std::uint32_t op, FoldReport& report) {
    FlatbufferView fb(bytes_);
    const auto opcode = fb.field_scalar<std::uint32_t>(op, schema::kOperatorOpcode, 0);
    if (opcode >= is_dequantize_.size() || !is_dequantize_[opcode]) return false;
    const auto inputs = fb.field_vector(op, schema::kOperatorInputs);
    const auto outputs = fb.field_vector(op, schema::kOperatorOutputs);
    if (inputs.size != 1 || outputs.size != 1) return false;
    const auto tensors = fb.field_vector(subgraph_, schema::kSubgraphTensors);
    const auto in_index = fb.vector_scalar<std::int32_t>(inputs, 0);
    const std::uint32_t in = fb.vector_table(tensors, static_cast<std::uint32_t>(in_index));
    if (fb.field_scalar<std::uint8_t>(in, schema::kTensorType, kFloat32) != kFloat16) return false;
    const auto buffer_index = fb.field_scalar<std::uint32_t>(in, schema::kTensorBuffer, 0);
    const auto buffers = fb.field_vector(model_, schema::kModelBuffers);
    const std::uint32_t buffer = fb.vector_table(buffers, buffer_index);
    const auto data = fb.field_vector(buffer, schema::kBufferData);
    const std::size_t n = element_count(fb, in);
    if (data.size != n * 2) return false;  // not a constant, or not all of it

    std::vector<float> values(n);
    for (std::size_t k = 0; k < n; ++k) {
      std::uint16_t h;
      std::memcpy(&h, bytes_.data() + data.first + 2 * k, 2);
      values[k] = half_to_float(h);
    }
    const std::uint32_t data_slot = fb.field_position(buffer, schema::kBufferData);
    const std::uint32_t type_slot = fb.field_position(in, schema::kTensorType);
    const std::uint32_t vector_at = append_float32_vector(bytes_, values);  // invalidates `fb`
    write_u32(data_slot, vector_at - data_slot);
    bytes_[type_slot] = kFloat32;
    replaced_[FlatbufferView(bytes_).vector_scalar<std::int32_t>(outputs, 0)] = in_index;
    ++report.dequantize_folded;
    report.float32_bytes_added += n * sizeof(float);
    return true;
  }

  // Every operator and the subgraph's outputs read the float32 constant
  // where they read the DEQUANTIZE's output.
  void rewire_inputs() {
    const FlatbufferView fb(bytes_);
    const auto operators = fb.field_vector(subgraph_, schema::kSubgraphOperators);
    for (std::uint32_t i = 0; i < operators.size; ++i) {
      rewire(fb.field_vector(fb.vector_table(operators, i), schema::kOperatorInputs));
    }
    rewire(fb.field_vector(subgraph_, schema::kSubgraphOutputs));
  }

  void rewire(const FlatbufferView::Vector& indices) {
    const FlatbufferView fb(bytes_);
    for (std::uint32_t k = 0; k < indices.size; ++k) {
      const auto it = replaced_.find(fb.vector_scalar<std::int32_t>(indices, k));
      if (it != replaced_.end()) write_u32(indices.first + 4 * k, static_cast<std::uint32_t>(it->second));
    }
  }

  // Drops the folded operators from the operators vector in place: each
  // kept offset moves to an earlier slot, so it grows by the distance
  // moved (offsets are relative to their own slot), and the length shrinks.
  std::size_t compact_operators(const std::vector<bool>& remove) {
    const FlatbufferView fb(bytes_);
    const auto operators = fb.field_vector(subgraph_, schema::kSubgraphOperators);
    std::uint32_t kept = 0;
    for (std::uint32_t i = 0; i < operators.size; ++i) {
      if (remove[i]) continue;
      const std::uint32_t offset = fb.vector_scalar<std::uint32_t>(operators, i);
      write_u32(operators.first + 4 * kept, offset + 4 * (i - kept));
      ++kept;
    }
    write_u32(operators.first - 4, kept);
    return kept;
  }

  void write_u32(std::uint32_t at, std::uint32_t value) { std::memcpy(bytes_.data() + at, &value, 4); }

  std::vector<std::uint8_t>& bytes_;
  std::uint32_t model_, subgraph_;
  const std::vector<bool>& is_dequantize_;
  std::map<std::int32_t, std::int32_t> replaced_;  // DEQUANTIZE output → its float32 input
};

}  // namespace

float half_to_float(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  std::uint32_t exponent = (h >> 10) & 0x1fu;
  std::uint32_t mantissa = h & 0x3ffu;
  std::uint32_t bits;
  if (exponent == 0x1f) {
    bits = sign | 0x7f800000u | (mantissa << 13);  // infinity or NaN
  } else if (exponent != 0) {
    bits = sign | ((exponent + 112) << 23) | (mantissa << 13);
  } else if (mantissa == 0) {
    bits = sign;  // ±0
  } else {
    // Subnormal: normalise the mantissa into a float32 normal.
    exponent = 113;
    while ((mantissa & 0x400u) == 0) {
      mantissa <<= 1;
      --exponent;
    }
    bits = sign | (exponent << 23) | ((mantissa & 0x3ffu) << 13);
  }
  return std::bit_cast<float>(bits);
}

FoldReport fold_float16_weights(std::vector<std::uint8_t>& model) {
  const FlatbufferView fb(model);
  if (model.size() < 8 || std::string(model.begin() + 4, model.begin() + 8) != "TFL3") {
    throw ModelFormatError("not a TFLite model (no TFL3 identifier)");
  }
  const std::uint32_t root = fb.root();
  std::vector<bool> is_dequantize;
  for (const std::int32_t code : builtin_codes(fb, root)) is_dequantize.push_back(code == kDequantize);
  const auto subgraphs = fb.field_vector(root, schema::kModelSubgraphs);
  FoldReport report;
  for (std::uint32_t s = 0; s < subgraphs.size; ++s) {
    const std::uint32_t subgraph = FlatbufferView(model).vector_table(subgraphs, s);
    SubgraphFolder(model, root, subgraph, is_dequantize).fold(report);
  }
  return report;
}

}  // namespace spinewatch::landmarks
