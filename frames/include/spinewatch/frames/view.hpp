#pragma once
// The station's two cameras (docs/interfaces.md §1), one enum for every module:
// recordings name their streams by it, the pairer keeps a queue per view,
// the estimator a silhouette and a cost per view. The values index arrays
// of two.
#include <cstdint>
#include <string_view>

namespace spinewatch {

enum class View : std::uint8_t { Frontal = 0, Lateral = 1 };
inline constexpr View kViews[] = {View::Frontal, View::Lateral};

inline constexpr std::size_t index_of(View view) { return static_cast<std::size_t>(view); }
inline constexpr std::string_view to_string(View view) { return view == View::Frontal ? "frontal" : "lateral"; }

}  // namespace spinewatch
