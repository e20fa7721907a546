#include "spinewatch/sync/trigger_master.hpp"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include <spdlog/spdlog.h>

#include "spinewatch/sync/edge_clock.hpp"
#include "spinewatch/frames/clock.hpp"

namespace spinewatch::sync {
namespace {
timespec to_timespec(std::int64_t ns) {
  return timespec{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
}

void sleep_until(std::int64_t deadline_ns) {
  const timespec ts = to_timespec(deadline_ns);
  while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

bool try_realtime(int priority) {
  if (priority <= 0) return false;
  sched_param param{};
  param.sched_priority = priority;
  const int rc = ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &param);
  if (rc != 0) {
    spdlog::warn("trigger: SCHED_FIFO priority {} refused ({}); running at normal priority, expect more jitter",
                 priority, std::strerror(rc));
    return false;
  }
  return true;
}
}  // namespace

TriggerMaster::TriggerMaster(TriggerOutputLine& line, TriggerMasterOptions options, EdgeCallback on_edge)
    : line_(line), options_(options), on_edge_(std::move(on_edge)) {
  thread_ = std::thread([this] { run(); });
}

TriggerMaster::~TriggerMaster() { stop(); }

void TriggerMaster::stop() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

void TriggerMaster::run() {
  realtime_.store(try_realtime(options_.realtime_priority));
  const auto period_ns = static_cast<std::int64_t>(std::llround(1e9 / (options_.fps > 0 ? options_.fps : 30.0)));
  const std::int64_t pulse_ns = std::clamp<std::int64_t>(std::int64_t{options_.pulse_us} * 1000, 1000, period_ns / 2);
  bool logged_error = false;
  auto drive = [&](bool high) {
    auto status = line_.set(high);
    if (status) return true;
    line_errors_.fetch_add(1);
    if (!logged_error) spdlog::error("trigger: {}", status.error().message);
    logged_error = true;
    return false;
  };

  // Deadlines are k × period from the start, never "now + period": a late
  // wake-up delays one edge, not every following one.
  const std::int64_t start = monotonic_now_ns() + period_ns;
  for (std::int64_t k = 0; !stop_.load(std::memory_order_relaxed); ++k) {
    const std::int64_t deadline = start + k * period_ns;
    sleep_until(deadline);
    const std::int64_t woke = monotonic_now_ns();
    if (!drive(true)) continue;
    const std::int64_t edge = monotonic_now_ns();
    latency_.add(woke - deadline);
    edges_.fetch_add(1);
    if (on_edge_) on_edge_(edge);
    // The fall is timed from the rise as it happened, not from its
    // deadline: a late wake-up must not shorten the pulse below what the
    // cameras need (from the deadline, a rise 1 ms late on a loaded host
    // left a 14 µs pulse). The rises stay on their absolute deadlines.
    sleep_until(edge + pulse_ns);
    drive(false);
  }
  (void)line_.set(false);
}

}  // namespace spinewatch::sync
