#include "spinewatch/frames/clock.hpp"

#include <time.h>

namespace spinewatch {
namespace {
std::int64_t read_clock(clockid_t id) {
  timespec ts{};
  ::clock_gettime(id, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}
}  // namespace

std::int64_t monotonic_now_ns() { return read_clock(CLOCK_MONOTONIC); }
std::int64_t realtime_now_ns() { return read_clock(CLOCK_REALTIME); }

}  // namespace spinewatch
