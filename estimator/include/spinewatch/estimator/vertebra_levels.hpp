#pragma once
#include <array>
#include <optional>
#include <string_view>

namespace spinewatch {

// Levels top to bottom (docs/interfaces.md §1).
inline constexpr std::size_t kVertebraCount = 17;
inline constexpr std::array<std::string_view, kVertebraCount> kVertebraNames = {
    "T1", "T2", "T3", "T4",  "T5",  "T6", "T7", "T8", "T9",
    "T10", "T11", "T12", "L1", "L2", "L3", "L4", "L5"};
inline constexpr std::size_t kNeckIndex = 0;    // T1
inline constexpr std::size_t kWaistIndex = 16;  // L5
inline constexpr std::size_t kFirstLumbarIndex = 12;  // L1

constexpr std::optional<std::size_t> vertebra_index(std::string_view name) {
  for (std::size_t i = 0; i < kVertebraCount; ++i)
    if (kVertebraNames[i] == name) return i;
  return std::nullopt;
}

}  // namespace spinewatch
