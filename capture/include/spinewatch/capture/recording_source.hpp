#pragma once
// A frame source over a recording, for the daemon and for tests: both
// streams merged in timestamp order, optionally paced at the recorded rate
// and looped. Frames are read one at a time, so a long recording can loop
// forever without being held in memory.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>

#include "spinewatch/capture/recording.hpp"

namespace spinewatch {

struct SourcedFrame {
  View view = View::Frontal;
  Frame frame;
};

struct RecordingSourceOptions {
  // Deliver each frame at its recorded time relative to the first (absolute
  // sleeps on CLOCK_MONOTONIC), with timestamps rebased to CLOCK_MONOTONIC:
  // t = start + (t_recorded − t_first). Otherwise as fast as next() is
  // called, with the recorded timestamps.
  bool paced = false;
  // Start again at the end. Each lap adds (recording length + one frame
  // period) to t_ns and (largest seq + 1) to seq, the same for both streams,
  // so seq and t keep increasing and frames still pair across the wrap.
  bool loop = false;
};

class RecordingSource {
 public:
  RecordingSource(RecordingReader reader, RecordingSourceOptions options);
  static Result<RecordingSource> open(const std::filesystem::path& dir, RecordingSourceOptions options);

  RecordingSource(RecordingSource&&) noexcept;
  RecordingSource& operator=(RecordingSource&&) noexcept;
  ~RecordingSource();

  // The next frame of either stream, earliest timestamp first (frontal first
  // on a tie). nullopt at the end (without loop), after stop(), or after a
  // read error (then error() says which; it is logged once).
  std::optional<SourcedFrame> next();
  // Thread-safe: makes a next() that is waiting for its frame's time return
  // nullopt promptly, and every later next() too.
  void stop();

  const RecordingInfo& info() const { return reader_.info(); }
  const std::optional<Error>& error() const { return error_; }

 private:
  struct Stream {
    std::size_t index = 0;  // next frame to deliver
    std::uint64_t lap = 0;
  };
  struct StopSignal;

  std::optional<View> next_view() const;
  std::int64_t lap_timestamp(View view, const Stream& stream) const;
  bool wait_until_due(std::int64_t offset_ns);

  RecordingReader reader_;
  RecordingSourceOptions options_;
  Stream streams_[2];
  std::int64_t first_t_ns_ = 0;   // earliest recorded timestamp of both streams
  std::int64_t lap_t_ns_ = 0;     // added to t_ns on each lap
  std::uint64_t lap_seq_ = 0;     // added to seq on each lap
  std::optional<std::int64_t> start_ns_;  // CLOCK_MONOTONIC of the first paced frame
  std::optional<Error> error_;
  std::unique_ptr<StopSignal> stop_;
};

}  // namespace spinewatch
