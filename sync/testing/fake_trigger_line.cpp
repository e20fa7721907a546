#include "spinewatch/sync/fake_trigger_line.hpp"

#include "spinewatch/sync/edge_clock.hpp"
#include "spinewatch/frames/clock.hpp"

namespace spinewatch::sync {

Status FakeTriggerLine::set(bool high) {
  const std::int64_t now = monotonic_now_ns();
  std::lock_guard lock(mutex_);
  // Like a GPIO line, setting the value it already has is not a transition.
  if (transitions_.empty() ? high : transitions_.back().high != high) transitions_.push_back({high, now});
  return Ok{};
}

Result<std::optional<std::int64_t>> FakeTriggerLine::wait_rising_edge(std::chrono::nanoseconds timeout) {
  std::unique_lock lock(mutex_);
  if (failures_ > 0) {
    --failures_;
    return Error{"fake line: read failed"};
  }
  if (!edge_ready_.wait_for(lock, timeout, [&] { return !edges_.empty(); })) return std::optional<std::int64_t>{};
  const std::int64_t t = edges_.front();
  edges_.pop_front();
  return std::optional<std::int64_t>{t};
}

void FakeTriggerLine::inject_rising_edge(std::int64_t t_ns) {
  {
    std::lock_guard lock(mutex_);
    edges_.push_back(t_ns);
  }
  edge_ready_.notify_all();
}

void FakeTriggerLine::fail_next_reads(int count) {
  std::lock_guard lock(mutex_);
  failures_ = count;
}

std::vector<FakeTriggerLine::Transition> FakeTriggerLine::transitions() const {
  std::lock_guard lock(mutex_);
  return transitions_;
}

}  // namespace spinewatch::sync
