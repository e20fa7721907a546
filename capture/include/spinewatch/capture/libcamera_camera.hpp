#pragma once
// A camera through libcamera (Raspberry Pi CSI sensors such as the IMX296
// or OV9281, or anything with a libcamera pipeline handler): the same
// Camera surface as V4l2Camera. Frames carry the sensor's frame sequence
// number and its CLOCK_MONOTONIC start-of-exposure time
// (controls::SensorTimestamp); a Frame leases its request's buffer and the
// request is queued again when the last copy goes. Gaps in the sequence
// count as drops; buffers libcamera reports as errors are dropped and
// counted. Built only when libcamera is found (SPINEWATCH_HAVE_LIBCAMERA);
// otherwise every call returns an error saying so.
//
// libcamera allows one CameraManager per process: every LibcameraCamera
// and list_libcamera_cameras() share one, started on first use and stopped
// when the last user goes.
#include <memory>
#include <string>
#include <vector>

#include "spinewatch/capture/camera.hpp"
#include "spinewatch/frames/pixel_format.hpp"

namespace spinewatch {

struct LibcameraCameraOptions {
  std::string id;    // libcamera camera id, as `spinewatch devices` lists it
  std::string name;  // for log lines ("frontal"); the id when empty
  PixelFormat pixel_format = PixelFormat::YUYV;  // GREY is libcamera's R8
  std::uint32_t width = 320;
  std::uint32_t height = 240;
  double fps = 30.0;     // FrameDurationLimits, when the camera has it
  int exposure_us = 0;   // 0: auto exposure; else ExposureTime with AeEnable off
  int gain = -1;         // −1: left to the camera; else AnalogueGain = gain (a multiplier, ≥ 1)
  unsigned buffers = 4;
};

struct LibcameraCameraInfo {
  std::string id;
  std::string model;                 // properties::Model, "" when unknown
  std::vector<std::string> formats;  // of a Viewfinder stream, e.g. "YUYV 320x240-1920x1080"
};

// Whether this build has libcamera support.
bool libcamera_built();
// The cameras libcamera sees (starts the shared camera manager).
Result<std::vector<LibcameraCameraInfo>> list_libcamera_cameras();

class LibcameraCamera final : public Camera {
 public:
  // Finds and acquires the camera; the error names the id and, when it is
  // not there, the ids that are.
  static Result<std::unique_ptr<LibcameraCamera>> open(LibcameraCameraOptions options);
  ~LibcameraCamera() override;
  LibcameraCamera(const LibcameraCamera&) = delete;
  LibcameraCamera& operator=(const LibcameraCamera&) = delete;

  // Configures (validate(): a camera that cannot give the format and size
  // exactly is an error naming what it offers instead), allocates and maps
  // the buffers, sets the controls and starts.
  Status start() override;
  std::optional<Frame> next(std::chrono::milliseconds timeout) override;
  void stop() override;

  CameraCounters counters() const override;
  FrameFormat format() const override;
  double fps() const override;
  const std::string& name() const override;

  struct State;  // shared with the frames' buffer leases

 private:
  explicit LibcameraCamera(std::shared_ptr<State> state);
  std::shared_ptr<State> state_;
};

}  // namespace spinewatch
