#include "spinewatch/capture/recorder.hpp"

#include <chrono>
#include <mutex>
#include <thread>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace spinewatch {

Recorder::Recorder(Camera& frontal, Camera& lateral, RecorderOptions options)
    : cameras_{&frontal, &lateral}, options_(std::move(options)) {}

void Recorder::stop() {
  stopping_.store(true);
  for (Camera* camera : cameras_) camera->stop();
}

Result<RecordingSummary> Recorder::record(const std::filesystem::path& dir) {
  const FrameFormat format = cameras_[0]->format();
  if (format != cameras_[1]->format())
    return Error{fmt::format("the cameras disagree on the format: frontal {}, lateral {}", describe(format),
                             describe(cameras_[1]->format()))};
  auto writer = RecordingWriter::create(dir, format, cameras_[0]->fps());
  if (!writer) return writer.error();

  RecordingSummary summary;
  std::mutex mutex;  // writer, on_frame, first_error
  std::optional<Error> first_error;
  const auto t0 = std::chrono::steady_clock::now();
  const auto out_of_time = [&] {
    return options_.seconds &&
           std::chrono::steady_clock::now() - t0 >= std::chrono::duration<double>(*options_.seconds);
  };
  auto capture = [&](int v) {
    std::uint64_t& written = summary.written[v];
    while (!stopping_.load() && (!options_.frames || written < *options_.frames) && !out_of_time()) {
      // Nothing on a timeout (the camera's watchdog reports a silent one) or after stop();
      // the short timeout keeps the duration check honest.
      auto frame = cameras_[v]->next(std::chrono::milliseconds(200));
      if (!frame) continue;
      std::lock_guard lock(mutex);
      if (auto w = writer->write(static_cast<View>(v), *frame); !w) {
        if (!first_error) first_error = w.error();
        stop();
        return;
      }
      ++written;
      if (options_.on_frame) options_.on_frame(static_cast<View>(v), *frame);
    }
  };
  {
    std::jthread threads[2] = {std::jthread(capture, 0), std::jthread(capture, 1)};
  }
  summary.stopped = stopping_.load() && !first_error;
  for (int v = 0; v < 2; ++v) summary.counters[v] = cameras_[v]->counters();
  if (first_error) return *first_error;

  if (auto finished = writer->finish(nullptr, options_.notes); !finished) return finished.error();
  if (options_.write_calibration)
    if (auto saved = options_.write_calibration(dir / "calibration.yaml"); !saved) return saved.error();
  return summary;
}

}  // namespace spinewatch
