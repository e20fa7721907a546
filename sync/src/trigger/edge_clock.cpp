#include "spinewatch/sync/edge_clock.hpp"

namespace spinewatch::sync {
namespace {
std::int64_t distance(std::int64_t a, std::int64_t b) { return a > b ? a - b : b - a; }
}  // namespace

EdgeClock classify_edge_clock(std::int64_t event_ns, std::int64_t monotonic_now_ns, std::int64_t realtime_now_ns) {
  // The two clocks are decades apart on any running system, so the nearer
  // one is the right one even for an event read seconds late.
  return distance(event_ns, realtime_now_ns) < distance(event_ns, monotonic_now_ns) ? EdgeClock::Realtime
                                                                                    : EdgeClock::Monotonic;
}

std::int64_t to_monotonic(EdgeClock clock, std::int64_t event_ns, std::int64_t monotonic_now_ns,
                          std::int64_t realtime_now_ns) {
  if (clock == EdgeClock::Monotonic) return event_ns;
  return event_ns - (realtime_now_ns - monotonic_now_ns);
}

}  // namespace spinewatch::sync
