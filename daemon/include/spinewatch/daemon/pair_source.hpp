#pragma once
// Where the daemon's frame pairs come from: cameras through the pairer, or a
// recording. The pipeline owns one and pulls from it on its source thread.
#include <cstdint>
#include <optional>
#include <string>

#include "spinewatch/frames/frame_pair.hpp"

namespace spinewatch {

// One camera's (or one view of a recording's) share.
struct CameraSourceStats {
  std::uint64_t frames = 0;    // delivered by this camera
  std::uint64_t restarts = 0;  // reopened after a device loss (cameras only)
  std::uint64_t losses = 0;    // the device went away (cameras only); each marked by a camera_lost line
};

struct SourceStats {
  std::uint64_t frames = 0;       // frames delivered by the camera(s) or recording
  std::uint64_t frames_lost = 0;  // frames that never became part of a pair (unpaired, driver drops)
  CameraSourceStats camera[2];    // frontal, lateral
};

class PairSource {
 public:
  virtual ~PairSource();
  // Blocks until the next pair; nothing at the end of the source or after stop().
  virtual std::optional<FramePair> next() = 0;
  // Called from another thread; makes a blocked next() return promptly.
  virtual void stop() = 0;
  // Safe to call from any thread.
  virtual SourceStats stats() const = 0;
  // For the hello line and the log: "v4l2", "recording /path", …
  virtual std::string describe() const = 0;
};

}  // namespace spinewatch
