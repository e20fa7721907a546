// The station's database (docs/storage.md) on real SQLite files: what is
// written, retention, and a database that cannot be written (full,
// read-only, nowhere), each counted while adding never waits.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <thread>

#include "storage/store.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

struct Db {
  explicit Db(const std::filesystem::path& path) { sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr); }
  ~Db() { sqlite3_close_v2(db); }
  std::string text(const std::string& sql) const {
    sqlite3_stmt* s = nullptr;
    std::string out;
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr) == SQLITE_OK && sqlite3_step(s) == SQLITE_ROW)
      out = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    else
      out = std::string("error: ") + sqlite3_errmsg(db);
    sqlite3_finalize(s);
    return out;
  }
  long count(const std::string& table) const { return std::stol(text("SELECT count(*) FROM " + table)); }
  sqlite3* db = nullptr;
};

TEST(Store, WritesEveryKindInWalModeAndReadsTheIntervalSummariesBack) {
  test::TempDir dir;
  const auto path = dir / "s.db";
  {
    Store store({.path = path});
    for (int i = 0; i < 100; ++i) store.add_posture(std::uint64_t(i), i * 33'333'333LL, "{\"class\":\"posture\",\"seq\":" + std::to_string(i) + "}");
    store.add_summary(SummaryScope::Interval, 0, 60, "", "{\"i\":1}");
    store.add_summary(SummaryScope::Shift, 0, 60, "", "{\"s\":1}");
    store.add_summary(SummaryScope::Interval, 60, 120, "w-17", "{\"i\":2}");
    store.add_alert(5, "{\"class\":\"alert\"}");
    store.add_event(NoteLevel::Info, "started");
    store.stop();
    EXPECT_EQ(store.stats().written, 105u);
    EXPECT_EQ(store.stats().dropped + store.stats().failed, 0u);
  }
  Db db(path);
  EXPECT_EQ(db.text("PRAGMA integrity_check"), "ok");
  EXPECT_EQ(db.text("PRAGMA journal_mode"), "wal");
  EXPECT_EQ(db.count("postures"), 100);
  EXPECT_EQ(db.text("SELECT max(seq) FROM postures"), "99");
  EXPECT_EQ(db.count("summaries"), 3);
  EXPECT_EQ(db.count("alerts"), 1);
  EXPECT_EQ(db.text("SELECT level || ' ' || message FROM events"), "info started");
  auto lines = read_stored_summary_lines(path);
  ASSERT_TRUE(lines) << lines.error().message;
  EXPECT_EQ(*lines, (std::vector<std::string>{"{\"i\":1}", "{\"i\":2}"}));
  auto missing = read_stored_summary_lines(dir / "nothing.db");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("nothing.db: no such database"), std::string::npos);
}

TEST(Store, RetentionDeletesRowsOlderThanThePeriod) {
  test::TempDir dir;
  const auto path = dir / "s.db";
  Store store({.path = path, .retention_days = 0.6 / 86400.0});  // 0.6 s
  for (int i = 0; i < 20; ++i) store.add_posture(std::uint64_t(i), i, "{}");
  std::this_thread::sleep_for(1500ms);  // retention runs every 0.2 s at this period
  store.add_posture(99, 99, "{}");
  std::this_thread::sleep_for(300ms);
  store.stop();
  EXPECT_EQ(store.stats().written, 21u);
  EXPECT_GE(store.stats().deleted, 20u);
  Db db(path);
  EXPECT_EQ(db.text("SELECT group_concat(seq) FROM postures"), "99");
}

TEST(Store, AFullDatabaseLosesRecordsCountedAndMakesRoomAgainThroughRetention) {
  test::TempDir dir;
  const auto path = dir / "s.db";
  // 64 kB may hold about 40 lines of 1 kB: the rest fails as on a full disk.
  Store store({.path = path, .retention_days = 1.0 / 86400.0, .max_size_mb = 0.0625});
  const std::string line(1000, 'x');
  // In small batches, as a running station adds them (a batch is one
  // transaction: all of it is written or none).
  for (int i = 0; i < 300; ++i) {
    store.add_posture(std::uint64_t(i), i, line);
    if (i % 5 == 4) std::this_thread::sleep_for(5ms);
  }
  std::this_thread::sleep_for(300ms);
  const StoreStats full = store.stats();
  EXPECT_GT(full.failed, 0u);
  EXPECT_GT(full.written, 0u);
  EXPECT_EQ(full.written + full.failed + full.dropped, 300u);
  // A second later those rows are past retention and deleted: room again.
  std::this_thread::sleep_for(1500ms);
  store.add_posture(1000, 1000, line);
  std::this_thread::sleep_for(300ms);
  store.stop();
  EXPECT_EQ(store.stats().written, full.written + 1);
  Db db(path);
  EXPECT_EQ(db.text("PRAGMA integrity_check"), "ok");
}

TEST(Store, ADatabaseThatCannotBeOpenedCountsEveryRecordAsFailed) {
  Store store({.path = "/nonexistent/spinewatch/s.db"});
  for (int i = 0; i < 50; ++i) store.add_posture(std::uint64_t(i), i, "{}");
  store.stop();
  EXPECT_EQ(store.stats().written, 0u);
  EXPECT_EQ(store.stats().failed, 50u);
}

TEST(Store, AReadOnlyFileIsCountedNotFatal) {
  test::TempDir dir;
  const auto path = dir / "s.db";
  {
    Store store({.path = path});
    store.add_event(NoteLevel::Info, "made");
  }
  // Root writes through file modes; an immutable file it cannot.
  if (test::run_command("chattr +i '" + path.string() + "'").exit_code != 0)
    GTEST_SKIP() << "chattr +i is not available on this file system (the read-only case needs it when run as root)";
  struct Unlock {
    std::filesystem::path p;
    ~Unlock() { test::run_command("chattr -i '" + p.string() + "'"); }
  } unlock{path};
  Store store({.path = path});
  for (int i = 0; i < 30; ++i) store.add_posture(std::uint64_t(i), i, "{}");
  store.stop();
  EXPECT_EQ(store.stats().written, 0u);
  EXPECT_EQ(store.stats().failed, 30u);
}

TEST(Store, AWriterThatFallsBehindDropsTheOldestCounted) {
  test::TempDir dir;
  Store store({.path = dir / "s.db", .queue = 4});
  for (int i = 0; i < 5000; ++i) store.add_posture(std::uint64_t(i), i, "{}");
  store.stop();
  const StoreStats s = store.stats();
  EXPECT_GT(s.dropped, 0u);
  EXPECT_EQ(s.written + s.dropped + s.failed, 5000u);
  EXPECT_EQ(Db(dir / "s.db").count("postures"), long(s.written));
}

}  // namespace
}  // namespace spinewatch
