#include "exposure/alert_output.hpp"

#include <spdlog/spdlog.h>


namespace spinewatch {

AlertOutput::AlertOutput(std::unique_ptr<sync::TriggerOutputLine> line, AlertOutputOptions options, std::string name)
    : line_(std::move(line)), options_(options), name_(std::move(name)), silent_(options.silent) {
  thread_ = std::thread([this] { run(); });
}

AlertOutput::~AlertOutput() { stop(); }

void AlertOutput::on_event(const AlertEvent& event) {
  {
    std::lock_guard lock(mutex_);
    if (event.change == AlertChange::Raised)
      raised_.insert(event.rule);
    else
      raised_.erase(event.rule);
  }
  wake_.notify_one();
}

void AlertOutput::set_silent(bool silent) {
  {
    std::lock_guard lock(mutex_);
    silent_ = silent;
  }
  wake_.notify_one();
}

bool AlertOutput::silent() const {
  std::lock_guard lock(mutex_);
  return silent_;
}

void AlertOutput::stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && !thread_.joinable()) return;
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
  line_.reset();  // the line's own destructor drives it inactive once more and releases it
}

AlertOutputStats AlertOutput::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

// Output thread. A write that fails is counted and logged when failures
// start and when they end; the next change tries again (`driven` is what
// was asked for either way, so a dead line is not retried in a loop).
void AlertOutput::write(bool active, bool& driven) {
  auto s = line_->set(active);
  driven = active;
  std::lock_guard lock(mutex_);
  if (!s) {
    ++stats_.write_errors;
    if (!failing_) spdlog::error("alerts: {}; the alert is not signalled (counted)", s.error().message);
    failing_ = true;
    return;
  }
  if (failing_) spdlog::info("alerts: {} written again", name_);
  failing_ = false;
}

void AlertOutput::run() {
  using clock = std::chrono::steady_clock;
  bool driven = false;       // the line as last written (requested inactive)
  bool signalling = false;   // an alert is being signalled (steady on, or pulsing)
  bool pulse_on = false;
  clock::time_point next_toggle{};
  std::unique_lock lock(mutex_);
  for (;;) {
    if (stopping_) break;
    const bool want = !raised_.empty() && !silent_;
    const auto now = clock::now();
    bool target = false;
    if (want && !signalling) {
      ++stats_.signalled;
      pulse_on = true;
      next_toggle = now + options_.pulse;
    } else if (want && options_.mode == AlertSignalMode::Pulse && now >= next_toggle) {
      pulse_on = !pulse_on;
      // From the planned time, so the pattern keeps its period; a late wake
      // (a loaded machine) starts afresh rather than toggling to catch up.
      next_toggle = now - next_toggle < options_.pulse ? next_toggle + options_.pulse : now + options_.pulse;
    }
    signalling = want;
    stats_.signalling = want;
    if (want) target = options_.mode == AlertSignalMode::Steady || pulse_on;
    if (target != driven) {
      lock.unlock();  // the event side never waits on a write
      write(target, driven);
      lock.lock();
      continue;  // look again: events may have come meanwhile
    }
    if (want && options_.mode == AlertSignalMode::Pulse)
      wake_.wait_until(lock, next_toggle);
    else
      wake_.wait(lock);
  }
  stats_.signalling = false;
  lock.unlock();
  if (driven) write(false, driven);
}

}  // namespace spinewatch
