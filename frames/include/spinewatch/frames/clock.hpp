#pragma once
// The clocks, read in one place. CLOCK_MONOTONIC is the time base of
// everything with a time in the pipeline: V4L2 buffer timestamps, GPIO edge
// events (Linux >= 5.7), paced replay, the frames' and postures' t_ns.
// std::chrono::steady_clock is the same clock in libstdc++, so deadlines
// built from these values wait on it too (pthread_cond_clockwait).
#include <cstdint>

namespace spinewatch {

std::int64_t monotonic_now_ns();
// Only to tell which clock a kernel stamped GPIO events with (sync/edge_clock.hpp).
std::int64_t realtime_now_ns();

}  // namespace spinewatch
