#pragma once
// The two camera streams as the pairer sees them. Kept apart from
// capture's View so that sync does not depend on capture; callers map
// View::Frontal → Stream::Frontal and so on (the values are equal).
#include <cstdint>
#include <string_view>

namespace spinewatch::sync {

enum class Stream : std::uint8_t { Frontal = 0, Lateral = 1 };
inline constexpr Stream kStreams[] = {Stream::Frontal, Stream::Lateral};

inline constexpr int index_of(Stream s) { return static_cast<int>(s); }
inline constexpr Stream other(Stream s) { return s == Stream::Frontal ? Stream::Lateral : Stream::Frontal; }
inline constexpr std::string_view to_string(Stream s) { return s == Stream::Frontal ? "frontal" : "lateral"; }

}  // namespace spinewatch::sync
