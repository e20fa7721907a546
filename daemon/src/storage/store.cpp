#include "storage/store.hpp"

#include <time.h>

#include <algorithm>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "storage/sqlite_db.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

// The writer wakes this often when nothing comes (retention, reopening);
// a record is committed as soon as the writer has taken it, so a crash
// loses what was queued and not yet taken: well under a second.
constexpr auto kIdleWake = 200ms;
constexpr auto kReopenEvery = 5s;
constexpr std::size_t kMaxBatch = 512;

constexpr const char* kSchema = R"(
CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY, value TEXT);
INSERT OR IGNORE INTO meta(key, value) VALUES ('schema', '1');
CREATE TABLE IF NOT EXISTS postures(stored_ns INTEGER NOT NULL, seq INTEGER, t_ns INTEGER, line TEXT NOT NULL);
CREATE INDEX IF NOT EXISTS postures_stored ON postures(stored_ns);
CREATE TABLE IF NOT EXISTS summaries(stored_ns INTEGER NOT NULL, scope TEXT NOT NULL, start_ns INTEGER, end_ns INTEGER,
                                     worker TEXT, line TEXT NOT NULL);
CREATE INDEX IF NOT EXISTS summaries_stored ON summaries(stored_ns);
CREATE TABLE IF NOT EXISTS alerts(stored_ns INTEGER NOT NULL, t_ns INTEGER, line TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS events(stored_ns INTEGER NOT NULL, level TEXT NOT NULL, message TEXT NOT NULL);
)";

}  // namespace

StoreOptions store_options(const Config& config) {
  StoreOptions o;
  o.path = config.storage.path;
  o.retention_days = config.storage.retention_days;
  o.max_size_mb = config.storage.max_size_mb;
  return o;
}

std::int64_t realtime_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

struct Store::Record {
  enum class Kind : std::uint8_t { Posture, Summary, Alert, Event } kind = Kind::Event;
  std::int64_t stored_ns = 0;
  std::int64_t a = 0, b = 0;  // posture: seq, t_ns; summary: start_ns, end_ns; alert: t_ns
  std::string tag, worker;    // summary: scope, worker; event: level
  std::string text;           // the line, or the event's message
};

// The connection and what it needs, on the writer thread only.
struct Store::Writer {
  explicit Writer(const StoreOptions& o) : options(o) {}
  const StoreOptions& options;
  sqlite::Db db;
  sqlite::Statement posture, summary, alert, event;
  std::chrono::steady_clock::time_point next_open{}, next_retention{};

  bool is_open() const { return db != nullptr; }

  Status open() {
    next_open = std::chrono::steady_clock::now() + kReopenEvery;
    auto opened = sqlite::open(options.path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX);
    if (!opened) return opened.error();
    sqlite3* d = opened->get();
    sqlite3_busy_timeout(d, 2000);
    // WAL: readers (spinewatch report) never block the writer, and a
    // killed process leaves every committed transaction in the file.
    auto mode = sqlite::prepare(d, "PRAGMA journal_mode=WAL");
    if (!mode) return mode.error();
    auto row = mode->step();
    if (!row) return row.error();
    const auto* text = *row ? sqlite3_column_text(mode->get(), 0) : nullptr;
    if (!text || std::string_view(reinterpret_cast<const char*>(text)) != "wal")
      return Error{"cannot switch to WAL mode (journal_mode stays " +
                   std::string(text ? reinterpret_cast<const char*>(text) : "unknown") + ")"};
    if (auto s = sqlite::exec(d, "PRAGMA synchronous=NORMAL"); !s) return s.error();
    if (options.max_size_mb > 0) {
      const auto pages = std::max<std::int64_t>(8, std::int64_t(options.max_size_mb * 1024 * 1024 / 4096));
      if (auto s = sqlite::exec(d, fmt::format("PRAGMA page_size=4096; PRAGMA max_page_count={}", pages).c_str()); !s)
        return s.error();
    }
    if (auto s = sqlite::exec(d, kSchema); !s) return s.error();
    auto p = sqlite::prepare(d, "INSERT INTO postures(stored_ns, seq, t_ns, line) VALUES (?, ?, ?, ?)");
    auto su = sqlite::prepare(d, "INSERT INTO summaries(stored_ns, scope, start_ns, end_ns, worker, line) VALUES (?, ?, ?, ?, ?, ?)");
    auto a = sqlite::prepare(d, "INSERT INTO alerts(stored_ns, t_ns, line) VALUES (?, ?, ?)");
    auto e = sqlite::prepare(d, "INSERT INTO events(stored_ns, level, message) VALUES (?, ?, ?)");
    for (auto* r : {&p, &su, &a, &e})
      if (!*r) return r->error();
    posture = std::move(p).value();
    summary = std::move(su).value();
    alert = std::move(a).value();
    event = std::move(e).value();
    db = std::move(opened).value();
    return Ok{};
  }

  void close() {
    for (auto* s : {&posture, &summary, &alert, &event}) *s = sqlite::Statement{};
    db.reset();
  }

  Status insert(const Record& r) {
    switch (r.kind) {
      case Record::Kind::Posture: return posture.bind(1, r.stored_ns).bind(2, r.a).bind(3, r.b).bind(4, r.text).run();
      case Record::Kind::Summary:
        return summary.bind(1, r.stored_ns).bind(2, r.tag).bind(3, r.a).bind(4, r.b).bind(5, r.worker).bind(6, r.text).run();
      case Record::Kind::Alert: return alert.bind(1, r.stored_ns).bind(2, r.a).bind(3, r.text).run();
      case Record::Kind::Event: return event.bind(1, r.stored_ns).bind(2, r.tag).bind(3, r.text).run();
    }
    return Ok{};
  }

  // One transaction: all of the batch or none of it.
  Status write(const std::vector<Record>& batch) {
    if (auto s = sqlite::exec(db.get(), "BEGIN"); !s) return s.error();
    for (const Record& r : batch) {
      if (auto s = insert(r); !s) {
        (void)sqlite::exec(db.get(), "ROLLBACK");
        return s.error();
      }
    }
    if (auto s = sqlite::exec(db.get(), "COMMIT"); !s) {
      (void)sqlite::exec(db.get(), "ROLLBACK");
      return s.error();
    }
    return Ok{};
  }

  Result<std::uint64_t> enforce_retention() {
    const std::int64_t cutoff = realtime_ns() - std::int64_t(options.retention_days * 86400e9);
    std::uint64_t deleted = 0;
    for (const char* table : {"postures", "summaries", "alerts", "events"}) {
      auto del = sqlite::prepare(db.get(), fmt::format("DELETE FROM {} WHERE stored_ns < ?", table));
      if (!del) return del.error();
      if (auto s = del->bind(1, cutoff).run(); !s) return s.error();
      deleted += std::uint64_t(sqlite3_changes(db.get()));
    }
    return deleted;
  }
};

Store::Store(StoreOptions options)
    : options_(std::move(options)), queue_(std::make_unique<BoundedQueue<Record>>(options_.queue)) {
  thread_ = std::jthread([this] { run(); });
}

Store::~Store() { stop(); }

void Store::stop() {
  if (stopped_) return;
  stopped_ = true;
  queue_->close();
  if (thread_.joinable()) thread_.join();
}

void Store::add(Record record) {
  record.stored_ns = realtime_ns();
  if (queue_->push(std::move(record))) dropped_.fetch_add(1, std::memory_order_relaxed);
}

void Store::add_posture(std::uint64_t seq, std::int64_t t_ns, std::string line) {
  add({Record::Kind::Posture, 0, std::int64_t(seq), t_ns, {}, {}, std::move(line)});
}
void Store::add_summary(SummaryScope scope, std::int64_t start_ns, std::int64_t end_ns, std::string worker,
                        std::string line) {
  add({Record::Kind::Summary, 0, start_ns, end_ns, std::string(to_string(scope)), std::move(worker), std::move(line)});
}
void Store::add_alert(std::int64_t t_ns, std::string line) { add({Record::Kind::Alert, 0, t_ns, 0, {}, {}, std::move(line)}); }
void Store::add_event(NoteLevel level, std::string message) {
  add({Record::Kind::Event, 0, 0, 0, std::string(to_string(level)), {}, std::move(message)});
}

StoreStats Store::stats() const {
  return {written_.load(std::memory_order_relaxed), dropped_.load(std::memory_order_relaxed),
          failed_.load(std::memory_order_relaxed), deleted_.load(std::memory_order_relaxed)};
}

void Store::run() {
  Writer w(options_);
  std::string failing;  // the error being counted; logged when it starts and when it ends
  std::uint64_t failed_since = 0;
  auto fail = [&](const Error& e, std::size_t records) {
    failed_.fetch_add(records, std::memory_order_relaxed);
    failed_since += records;
    if (failing != e.message)
      spdlog::error("storage: {}: {}; records are lost (counted) until it can be written again",
                    options_.path.string(), e.message);
    failing = e.message;
  };
  auto recovered = [&] {
    if (failing.empty()) return;
    spdlog::info("storage: {}: writing again ({} records lost meanwhile)", options_.path.string(), failed_since);
    failing.clear();
    failed_since = 0;
  };
  std::vector<Record> batch;
  for (;;) {
    auto first = queue_->pop_for(kIdleWake);
    if (!first && queue_->closed()) break;
    if (first) {
      batch.push_back(std::move(*first));
      while (batch.size() < kMaxBatch)
        if (auto more = queue_->pop_for(0ms)) batch.push_back(std::move(*more));
        else break;
    }
    const auto now = std::chrono::steady_clock::now();
    if (!w.is_open() && now >= w.next_open) {
      if (auto s = w.open(); !s) {
        w.close();
        fail(s.error(), 0);
      } else {
        spdlog::info("storage: {} (WAL; retention {} days)", options_.path.string(), options_.retention_days);
      }
    }
    if (batch.empty()) {
      // Nothing to write: time for retention.
    } else if (!w.is_open()) {
      fail(Error{failing.empty() ? "not open" : failing}, batch.size());
    } else if (auto s = w.write(batch); !s) {
      fail(s.error(), batch.size());
    } else {
      written_.fetch_add(batch.size(), std::memory_order_relaxed);
      recovered();
    }
    batch.clear();
    if (w.is_open() && now >= w.next_retention) {
      // Often enough that nothing outlives the period by more than a tenth of it.
      const auto period = std::chrono::duration<double>(std::clamp(options_.retention_days * 86400.0 / 10.0, 0.2, 60.0));
      w.next_retention = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
      if (auto deleted = w.enforce_retention()) deleted_.fetch_add(*deleted, std::memory_order_relaxed);
      else fail(deleted.error(), 0);
    }
  }
  w.close();
}

Result<std::vector<std::string>> read_stored_summary_lines(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return Error{fmt::format("{}: no such database", path.string())};
  auto db = sqlite::open(path, SQLITE_OPEN_READONLY);
  if (!db) return Error{fmt::format("{}: {}", path.string(), db.error().message)};
  auto q = sqlite::prepare(db->get(), "SELECT line FROM summaries WHERE scope = 'interval' ORDER BY rowid");
  if (!q) return Error{fmt::format("{}: {}", path.string(), q.error().message)};
  std::vector<std::string> lines;
  for (;;) {
    auto row = q->step();
    if (!row) return Error{fmt::format("{}: {}", path.string(), row.error().message)};
    if (!*row) break;
    lines.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(q->get(), 0)));
  }
  return lines;
}

Result<std::vector<StoredLine>> read_stored_posture_lines(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return Error{fmt::format("{}: no such database", path.string())};
  auto db = sqlite::open(path, SQLITE_OPEN_READONLY);
  if (!db) return Error{fmt::format("{}: {}", path.string(), db.error().message)};
  auto q = sqlite::prepare(db->get(), "SELECT stored_ns, line FROM postures ORDER BY rowid");
  if (!q) return Error{fmt::format("{}: {}", path.string(), q.error().message)};
  std::vector<StoredLine> lines;
  for (;;) {
    auto row = q->step();
    if (!row) return Error{fmt::format("{}: {}", path.string(), row.error().message)};
    if (!*row) break;
    lines.push_back({sqlite3_column_int64(q->get(), 0), reinterpret_cast<const char*>(sqlite3_column_text(q->get(), 1))});
  }
  return lines;
}

}  // namespace spinewatch
