#pragma once
// What every camera source offers its consumer (the recorder, the daemon's
// pair source): start, every frame in driver order with its sequence number
// and CLOCK_MONOTONIC timestamp, stop from any thread, and counters. A
// Frame holds its buffer until the last copy goes; the camera reuses the
// buffer only then. V4l2Camera and LibcameraCamera implement it.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "spinewatch/frames/frame.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// Read from any thread.
struct CameraCounters {
  std::uint64_t frames = 0;         // delivered to the caller
  std::uint64_t dropped_error = 0;  // frames the driver flagged bad, or short frames
  std::uint64_t dropped_gap = 0;    // gaps in the driver's sequence numbers
  std::uint64_t restarts = 0;       // reopened after a device loss
  std::uint64_t stalls = 0;         // watchdog reports
  std::uint64_t losses = 0;         // the device went away (unplugged, disconnected); counted when seen
};

class Camera {
 public:
  virtual ~Camera() = default;

  // Opens, configures and starts streaming; the error names the camera and the problem.
  virtual Status start() = 0;
  // The next frame in driver order; nothing on timeout or once stopped (a
  // negative timeout waits until a frame comes or stop()). One thread only.
  virtual std::optional<Frame> next(std::chrono::milliseconds timeout) = 0;
  // From any thread: wakes next() and makes it return nothing from now on.
  virtual void stop() = 0;

  virtual CameraCounters counters() const = 0;
  virtual FrameFormat format() const = 0;  // as negotiated
  virtual double fps() const = 0;          // as the driver reported it
  virtual const std::string& name() const = 0;
};

}  // namespace spinewatch
