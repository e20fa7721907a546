#include "spinewatch/daemon/testing/fake_pair_source.hpp"

#include <utility>
#include <vector>

namespace spinewatch::test {

std::optional<FramePair> FakePairSource::next() {
  if (stopped_) return std::nullopt;
  if (produced_ >= options_.count) {
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
  std::vector<std::uint8_t> pixels(format.frame_bytes(), static_cast<std::uint8_t>(i));
  pair.frontal = Frame::owning(format, {own_seq, pair.timestamp_ns}, pixels);
  pair.lateral = Frame::owning(format, {own_seq, pair.timestamp_ns}, std::move(pixels));
  frames_ += 2;
  return pair;
}

void FakePairSource::stop() {
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
  }
  stop_cv_.notify_all();
}

SourceStats FakePairSource::stats() const {
  SourceStats s;
  s.frames = frames_.load();
  return s;
}

Posture lost_posture(const FramePair& pair) {
  Posture p;
  p.seq = pair.sequence;
  p.t_ns = pair.timestamp_ns;
  p.state = TrackingState::Lost;
  return p;
}

}  // namespace spinewatch::test
