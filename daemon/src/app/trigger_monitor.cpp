#include "app/trigger_monitor.hpp"

#include <spdlog/spdlog.h>

namespace spinewatch {

namespace {

// Configure the box for the camera rate and pulse width and start it.
Result<std::unique_ptr<sync::TriggerController>> start_controller(const std::string& device, double rate_hz,
                                                                  int pulse_us) {
  auto controller = sync::TriggerController::open(device);
  if (!controller) return controller.error();
  auto& c = **controller;
  auto version = c.version();
  if (!version) return version.error();
  if (auto s = c.configure({.rate_hz = rate_hz, .width_us = pulse_us}); !s) return s.error();
  if (auto s = c.start(); !s) return s.error();
  auto status = c.status();
  if (!status) return status.error();
  spdlog::info("trigger controller {}: firmware {} (protocol {}); {}", c.device(), version->firmware,
               version->protocol, sync::describe(*status));
  return controller;
}

}  // namespace

TriggerMonitor::TriggerMonitor(const Config& config)
    : device_(config.trigger.controller), rate_hz_(config.cameras.fps), pulse_us_(config.trigger.pulse_us) {}

std::string TriggerMonitor::status() const { return state_ == State::Failing ? "error: " + text_ : text_; }

void TriggerMonitor::fail(std::string message) {
  state_ = State::Failing;
  text_ = std::move(message);
}

void TriggerMonitor::poll() {
  if (!configured()) return;
  if (!controller_) {
    const auto now = std::chrono::steady_clock::now();
    if (now < next_attempt_) return;
    next_attempt_ = now + kRetry;
    auto controller = start_controller(device_, rate_hz_, pulse_us_);
    if (!controller) {
      if (state_ != State::Failing) spdlog::error("{} (retrying every {} s)", controller.error().message, kRetry.count());
      fail(controller.error().message);
      return;
    }
    if (state_ == State::Failing) spdlog::info("trigger controller {} set up", device_);
    controller_ = std::move(controller).value();
    state_ = State::NotAsked;
    text_.clear();
  }
  auto status = controller_->status();
  if (status) {
    if (state_ == State::Failing) spdlog::info("trigger controller answers again");
    state_ = State::Answering;
    text_ = sync::describe(*status);
  } else {
    if (state_ != State::Failing) spdlog::error("{}", status.error().message);
    fail(status.error().message);
  }
}

}  // namespace spinewatch
