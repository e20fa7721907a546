#include "storage/sqlite_db.hpp"

#include <fmt/format.h>

namespace spinewatch::sqlite {

std::string message(sqlite3* db) { return db ? sqlite3_errmsg(db) : "out of memory"; }

Status Statement::run() {
  int rc;
  while ((rc = sqlite3_step(stmt_.get())) == SQLITE_ROW) {
  }
  sqlite3_reset(stmt_.get());
  sqlite3_clear_bindings(stmt_.get());
  if (rc != SQLITE_DONE) return Error{message(db_)};
  return Ok{};
}

Result<bool> Statement::step() {
  const int rc = sqlite3_step(stmt_.get());
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  return Error{message(db_)};
}

Result<Db> open(const std::filesystem::path& path, int flags) {
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &raw, flags, nullptr);
  Db db(raw);
  if (rc != SQLITE_OK) return Error{message(raw)};
  sqlite3_extended_result_codes(raw, 1);
  return db;
}

Result<Statement> prepare(sqlite3* db, std::string_view sql) {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(db, sql.data(), int(sql.size()), &s, nullptr) != SQLITE_OK) return Error{message(db)};
  return Statement(db, s);
}

Status exec(sqlite3* db, const char* sql) {
  char* error = nullptr;
  if (sqlite3_exec(db, sql, nullptr, nullptr, &error) != SQLITE_OK) {
    std::string text = error ? error : message(db);
    sqlite3_free(error);
    return Error{text};
  }
  return Ok{};
}

}  // namespace spinewatch::sqlite
