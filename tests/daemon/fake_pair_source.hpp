#pragma once
// A PairSource for tests: synthetic 320×240 GREY pairs, as fast as asked
// or until a count, restarting its own numbering every `lap` pairs the way a
// looping recording might.
#include <atomic>
#include <condition_variable>
#include <mutex>

#include "spinewatch/daemon/pair_source.hpp"
#include "spinewatch/estimator/posture.hpp"

namespace spinewatch::test {

class FakePairSource final : public PairSource {
 public:
  struct Options {
    std::uint64_t count = 100;  // pairs before the end; 0: block after none (until stop)
    std::uint64_t lap = 0;      // numbering restarts every `lap` pairs (0: never)
    std::uint32_t width = 320, height = 240;
    std::uint64_t camera_lost_at = 0;  // a camera_lost marker before this pair (0: none)
  };
  explicit FakePairSource(Options options) : options_(options) {}

  std::optional<FramePair> next() override {
    if (stopped_) return std::nullopt;
    if (produced_ >= options_.count) {
      // Like a camera with nothing more to say: wait for stop().
      std::unique_lock lock(mutex_);
      stop_cv_.wait(lock, [&] { return stopped_.load(); });
      return std::nullopt;
    }
    if (options_.camera_lost_at != 0 && produced_ == options_.camera_lost_at && !marked_) {
      marked_ = true;
      FramePair marker;
      marker.timestamp_ns = static_cast<std::int64_t>(1'000'000'000 + produced_ * 33'333'333 - 1);
      marker.camera_lost = true;
      return marker;
    }
    const std::uint64_t i = produced_++;
    const std::uint64_t own_seq = options_.lap ? i % options_.lap : i;
    FramePair pair;
    pair.sequence = own_seq;
    pair.timestamp_ns = static_cast<std::int64_t>(1'000'000'000 + i * 33'333'333);
    const auto format = FrameFormat::packed(PixelFormat::GREY, options_.width, options_.height);
    std::vector<std::uint8_t> pixels(format.frame_bytes(),
                                     static_cast<std::uint8_t>(i));
    pair.frontal = Frame::owning(format, {own_seq, pair.timestamp_ns}, pixels);
    pair.lateral = Frame::owning(format, {own_seq, pair.timestamp_ns}, std::move(pixels));
    frames_ += 2;
    return pair;
  }
  void stop() override {
    {
      std::lock_guard lock(mutex_);
      stopped_ = true;
    }
    stop_cv_.notify_all();
  }
  SourceStats stats() const override {
    SourceStats s;
    s.frames = frames_.load();
    return s;
  }
  std::string describe() const override { return "fake"; }

 private:
  Options options_;
  std::uint64_t produced_ = 0;
  bool marked_ = false;
  std::atomic<std::uint64_t> frames_{0};
  std::atomic<bool> stopped_{false};
  std::mutex mutex_;
  std::condition_variable stop_cv_;
};

// The stand-in estimator: reports every pair lost, as the brief allows for tests.
inline Posture lost_posture(const FramePair& pair) {
  Posture p;
  p.seq = pair.sequence;
  p.t_ns = pair.timestamp_ns;
  p.state = TrackingState::Lost;
  return p;
}

}  // namespace spinewatch::test
