#include "spinewatch/capture/recording_source.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <limits>
#include <mutex>

#include <spdlog/spdlog.h>

#include "spinewatch/frames/clock.hpp"

namespace spinewatch {
namespace {

}  // namespace

struct RecordingSource::StopSignal {
  std::mutex mutex;
  std::condition_variable wake;
  bool stopped = false;
};

RecordingSource::RecordingSource(RecordingReader reader, RecordingSourceOptions options)
    : reader_(std::move(reader)), options_(options), stop_(std::make_unique<StopSignal>()) {
  std::int64_t first = std::numeric_limits<std::int64_t>::max();
  std::int64_t last = std::numeric_limits<std::int64_t>::min();
  std::uint64_t last_seq = 0;
  for (View view : kViews) {
    const auto& frames = reader_.info().frames[static_cast<int>(view)];
    if (frames.empty()) continue;
    first = std::min(first, frames.front().timestamp_ns);
    last = std::max(last, frames.back().timestamp_ns);
    last_seq = std::max(last_seq, frames.back().sequence);
  }
  if (first > last) return;  // no frames at all: next() ends at once
  first_t_ns_ = first;
  const auto period = static_cast<std::int64_t>(std::llround(1e9 / reader_.info().fps));
  lap_t_ns_ = (last - first) + period;
  lap_seq_ = last_seq + 1;
}

RecordingSource::RecordingSource(RecordingSource&&) noexcept = default;
RecordingSource& RecordingSource::operator=(RecordingSource&&) noexcept = default;
RecordingSource::~RecordingSource() = default;

Result<RecordingSource> RecordingSource::open(const std::filesystem::path& dir, RecordingSourceOptions options) {
  auto reader = RecordingReader::open(dir);
  if (!reader) return reader.error();
  return RecordingSource(std::move(*reader), options);
}

void RecordingSource::stop() {
  {
    std::lock_guard lock(stop_->mutex);
    stop_->stopped = true;
  }
  stop_->wake.notify_all();
}

std::int64_t RecordingSource::lap_timestamp(View view, const Stream& stream) const {
  const auto& frames = reader_.info().frames[static_cast<int>(view)];
  return frames[stream.index].timestamp_ns + static_cast<std::int64_t>(stream.lap) * lap_t_ns_;
}

std::optional<View> RecordingSource::next_view() const {
  std::optional<View> best;
  std::int64_t best_t = 0;
  for (View view : kViews) {
    const auto& stream = streams_[static_cast<int>(view)];
    if (stream.index >= reader_.frame_count(view)) continue;
    const auto t = lap_timestamp(view, stream);
    if (!best || t < best_t) {
      best = view;
      best_t = t;
    }
  }
  return best;
}

bool RecordingSource::wait_until_due(std::int64_t offset_ns) {
  using namespace std::chrono;
  const steady_clock::time_point deadline{duration_cast<steady_clock::duration>(nanoseconds(*start_ns_ + offset_ns))};
  std::unique_lock lock(stop_->mutex);
  stop_->wake.wait_until(lock, deadline, [this] { return stop_->stopped; });
  return !stop_->stopped;
}

std::optional<SourcedFrame> RecordingSource::next() {
  {
    std::lock_guard lock(stop_->mutex);
    if (stop_->stopped) return std::nullopt;
  }
  if (error_) return std::nullopt;
  const auto view = next_view();
  if (!view) return std::nullopt;

  auto& stream = streams_[static_cast<int>(*view)];
  // Read before waiting, so the frame goes out as close to its time as possible.
  auto read = reader_.read(*view, stream.index);
  if (!read) {
    spdlog::error("{}", read.error().message);
    error_ = read.error();
    return std::nullopt;
  }

  FrameInfo info = read->info();
  info.sequence += stream.lap * lap_seq_;
  info.timestamp_ns = lap_timestamp(*view, stream);
  if (options_.paced) {
    if (!start_ns_) start_ns_ = monotonic_now_ns();
    const auto offset = info.timestamp_ns - first_t_ns_;
    if (!wait_until_due(offset)) return std::nullopt;
    info.timestamp_ns = *start_ns_ + offset;
  }

  if (++stream.index == reader_.frame_count(*view) && options_.loop) {
    stream.index = 0;
    ++stream.lap;
  }
  // The read frame stays the owner of the bytes; only its metadata changes.
  auto holder = std::make_shared<const Frame>(std::move(*read));
  return SourcedFrame{*view, Frame(holder->format(), info, holder, holder->bytes())};
}

}  // namespace spinewatch
