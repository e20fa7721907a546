#pragma once
// GPIO event timestamps come from the kernel: CLOCK_MONOTONIC since Linux
// 5.7, CLOCK_REALTIME before. Which one a kernel uses is told by comparing
// an event's stamp with both clocks when it is read.
#include <cstdint>

namespace spinewatch::sync {

enum class EdgeClock { Monotonic, Realtime };

// The clock `event_ns` most plausibly came from, given both clocks read just
// after the event was read (the event happened shortly before).
EdgeClock classify_edge_clock(std::int64_t event_ns, std::int64_t monotonic_now_ns, std::int64_t realtime_now_ns);
// `event_ns` on CLOCK_MONOTONIC.
std::int64_t to_monotonic(EdgeClock clock, std::int64_t event_ns, std::int64_t monotonic_now_ns,
                          std::int64_t realtime_now_ns);

}  // namespace spinewatch::sync
