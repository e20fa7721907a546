#pragma once
// The station's database (docs/storage.md): postures (every Nth),
// exposure summaries and the daemon's own events, in SQLite (WAL), written
// by one thread of its own from a bounded queue. Adding never blocks and
// never fails: a full queue drops the oldest record, a database that
// cannot be written (read-only, disk full, missing) loses the records it
// was given — each counted and logged, the pipeline untouched.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/stored_lines.hpp"
#include "spinewatch/estimator/load/exposure_summary.hpp"
#include "spinewatch/frames/result.hpp"
#include "support/bounded_queue.hpp"
#include "support/note_level.hpp"

namespace spinewatch {

struct StoreOptions {
  std::filesystem::path path;
  double retention_days = 90;  // rows older than this (by when they were stored) are deleted
  double max_size_mb = 0;      // the database may grow to this; 0 = as the disk allows
  std::size_t queue = 8192;    // records waiting for the writer before the oldest is dropped
};

struct StoreStats {
  std::uint64_t written = 0;  // records committed
  std::uint64_t dropped = 0;  // records the queue dropped (the writer fell behind)
  std::uint64_t failed = 0;   // records lost to a database error
  std::uint64_t deleted = 0;  // rows deleted for retention
};

class Store {
 public:
  explicit Store(StoreOptions options);  // starts the writer; it opens the database
  ~Store();                              // stop()
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  // Any thread; never blocks on the database. `line` is the stream line.
  void add_posture(std::uint64_t seq, std::int64_t t_ns, std::string line);
  void add_summary(SummaryScope scope, std::int64_t start_ns, std::int64_t end_ns, std::string worker, std::string line);
  void add_alert(std::int64_t t_ns, std::string line);
  void add_event(NoteLevel level, std::string message);
  // Writes what is queued, closes the database, joins. Idempotent.
  void stop();

  StoreStats stats() const;
  const StoreOptions& options() const { return options_; }

 private:
  struct Record;
  struct Writer;
  void add(Record record);
  void run();

  StoreOptions options_;
  std::unique_ptr<BoundedQueue<Record>> queue_;
  std::atomic<std::uint64_t> written_{0}, dropped_{0}, failed_{0}, deleted_{0};
  std::jthread thread_;
  bool stopped_ = false;
};

// [storage]: the database's settings.
StoreOptions store_options(const Config& config);

// CLOCK_REALTIME in nanoseconds.
std::int64_t realtime_ns();

}  // namespace spinewatch
