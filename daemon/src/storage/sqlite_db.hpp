#pragma once
// RAII for the SQLite C API, as far as the store needs it: a connection and
// prepared statements, errors as values carrying sqlite3_errmsg.
#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::sqlite {

struct CloseDb {
  void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
struct Finalize {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Db = std::unique_ptr<sqlite3, CloseDb>;

class Statement {
 public:
  Statement() = default;
  Statement(sqlite3* db, sqlite3_stmt* s) : db_(db), stmt_(s) {}
  Statement& bind(int index, std::int64_t v) {
    sqlite3_bind_int64(stmt_.get(), index, v);
    return *this;
  }
  Statement& bind(int index, std::string_view v) {
    sqlite3_bind_text(stmt_.get(), index, v.data(), int(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  // Runs to completion (resetting for the next use); SQLITE_ROW results are skipped.
  Status run();
  // One step: true with a row, false when done.
  Result<bool> step();
  sqlite3_stmt* get() const { return stmt_.get(); }

 private:
  sqlite3* db_ = nullptr;
  std::unique_ptr<sqlite3_stmt, Finalize> stmt_;
};

Result<Db> open(const std::filesystem::path& path, int flags);
Result<Statement> prepare(sqlite3* db, std::string_view sql);
Status exec(sqlite3* db, const char* sql);
std::string message(sqlite3* db);

}  // namespace spinewatch::sqlite
