#include "spinewatch/landmarks/tflite_resize.hpp"

#include "flatbuffer_view.hpp"
#include "tflite_schema.hpp"

namespace spinewatch::landmarks {

std::set<std::size_t> half_pixel_resizes(const std::vector<std::uint8_t>& model) {
  const FlatbufferView fb(model);
  const std::uint32_t root = fb.root();
  const auto codes = builtin_codes(fb, root);
  std::set<std::size_t> found;
  const auto subgraphs = fb.field_vector(root, schema::kModelSubgraphs);
  if (subgraphs.size == 0) return found;
  const auto operators = fb.field_vector(fb.vector_table(subgraphs, 0), schema::kSubgraphOperators);
  for (std::uint32_t i = 0; i < operators.size; ++i) {
    const std::uint32_t op = fb.vector_table(operators, i);
    const auto opcode = fb.field_scalar<std::uint32_t>(op, schema::kOperatorOpcode, 0);
    if (opcode >= codes.size() || codes[opcode] != schema::kResizeBilinear) continue;
    const std::uint32_t options = fb.field_table(op, schema::kOperatorBuiltinOptions);
    if (options != 0 && fb.field_scalar<std::uint8_t>(options, schema::kResizeHalfPixelCenters, 0) != 0) {
      found.insert(i);
    }
  }
  return found;
}

}  // namespace spinewatch::landmarks
