#pragma once
// Bounds-checked reads of a flatbuffer's tables and vectors by field slot,
// without a generated schema: only what the TFLite fold needs.
#include <cstdint>
#include <cstring>
#include <vector>

#include "spinewatch/landmarks/tflite_fold.hpp"

namespace spinewatch::landmarks {

class FlatbufferView {
 public:
  struct Vector {
    std::uint32_t first = 0;  // position of element 0 (the length word is 4 bytes before)
    std::uint32_t size = 0;
  };

  explicit FlatbufferView(const std::vector<std::uint8_t>& bytes) : bytes_(bytes) {}

  std::uint32_t root() const { return follow(0); }

  // Position of field `slot` of the table at `table`, 0 when absent.
  std::uint32_t field_position(std::uint32_t table, int slot) const {
    const auto vtable = static_cast<std::uint32_t>(static_cast<std::int64_t>(table) - read<std::int32_t>(table));
    const auto vtable_size = read<std::uint16_t>(vtable);
    const std::uint32_t entry = 4 + 2 * static_cast<std::uint32_t>(slot);
    if (entry + 2 > vtable_size) return 0;
    const auto offset = read<std::uint16_t>(vtable + entry);
    return offset == 0 ? 0 : table + offset;
  }

  template <typename T>
  T field_scalar(std::uint32_t table, int slot, T fallback) const {
    const std::uint32_t at = field_position(table, slot);
    return at == 0 ? fallback : read<T>(at);
  }

  // The table a field points at, 0 when the field is absent.
  std::uint32_t field_table(std::uint32_t table, int slot) const {
    const std::uint32_t at = field_position(table, slot);
    return at == 0 ? 0 : follow(at);
  }

  // The vector a field points at; empty when the field is absent.
  Vector field_vector(std::uint32_t table, int slot) const {
    const std::uint32_t at = field_position(table, slot);
    if (at == 0) return {};
    const std::uint32_t vector = follow(at);
    const Vector v{vector + 4, read<std::uint32_t>(vector)};
    check(v.first, static_cast<std::size_t>(v.size));  // at least one byte per element
    return v;
  }

  template <typename T>
  T vector_scalar(const Vector& v, std::uint32_t i) const {
    if (i >= v.size) throw ModelFormatError("flatbuffer: vector index out of range");
    return read<T>(v.first + static_cast<std::uint32_t>(sizeof(T)) * i);
  }

  std::uint32_t vector_table(const Vector& v, std::uint32_t i) const {
    if (i >= v.size) throw ModelFormatError("flatbuffer: vector index out of range");
    return follow(v.first + 4 * i);
  }

 private:
  std::uint32_t follow(std::uint32_t at) const {
    const std::uint64_t target = static_cast<std::uint64_t>(at) + read<std::uint32_t>(at);
    if (target >= bytes_.size()) throw ModelFormatError("flatbuffer: offset out of range");
    return static_cast<std::uint32_t>(target);
  }

  void check(std::uint64_t at, std::size_t size) const {
    if (at + size > bytes_.size()) throw ModelFormatError("flatbuffer: read out of range");
  }

  template <typename T>
  T read(std::uint32_t at) const {
    check(at, sizeof(T));
    T value;
    std::memcpy(&value, bytes_.data() + at, sizeof(T));
    return value;
  }

  const std::vector<std::uint8_t>& bytes_;
};

}  // namespace spinewatch::landmarks
