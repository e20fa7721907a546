#pragma once
// The capture loop of `spinewatch record`: every frame of two started
// cameras, in driver order, into a recording directory (docs/interfaces.md §2)
// with the driver's sequence numbers and timestamps, until a frame count,
// a duration or stop(). One thread per camera, so that a slow or silent
// camera never holds up the other.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "spinewatch/capture/camera.hpp"
#include "spinewatch/capture/recording.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct RecorderOptions {
  std::optional<std::uint64_t> frames;  // stop once each camera has given this many
  std::optional<double> seconds;        // stop after this long
  std::string notes;                    // recording.json "notes"
  // Writes DIR/calibration.yaml: the caller's rig (capture does not know
  // the estimator's camera model). Nothing: no calibration.yaml.
  std::function<Status(const std::filesystem::path&)> write_calibration;
  // Sees every frame written, from that camera's thread; calls are
  // serialised by the recorder (the CLI feeds its pairing report).
  std::function<void(View, const Frame&)> on_frame;
};

struct RecordingSummary {
  std::uint64_t written[2] = {0, 0};  // frontal, lateral
  CameraCounters counters[2];
  bool stopped = false;  // ended by stop(), not by the frame count or duration
};

class Recorder {
 public:
  // The cameras must outlive the recorder and be started before record().
  Recorder(Camera& frontal, Camera& lateral, RecorderOptions options);
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Creates `dir` and records into it; returns once both cameras are done.
  // Errors: the cameras' formats differ, the directory or a file cannot be
  // written, a stream got no frames.
  Result<RecordingSummary> record(const std::filesystem::path& dir);

  // From any thread (the CLI's signal thread): the recording ends cleanly,
  // with what was written so far. Stops the cameras.
  void stop();

 private:
  Camera* cameras_[2];
  RecorderOptions options_;
  std::atomic<bool> stopping_{false};
};

}  // namespace spinewatch
