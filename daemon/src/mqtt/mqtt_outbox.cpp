#include "mqtt/mqtt_outbox.hpp"

#include <fmt/format.h>

#include "storage/sqlite_db.hpp"

namespace spinewatch {

struct MqttOutbox::Impl {
  std::filesystem::path path;
  std::size_t max_messages = 0;
  sqlite::Db db;
  sqlite::Statement insert, drop, select_after, remove, count;

  // Every message's topic is one this daemon publishes: the names are
  // parsed once, here, and the messages read later carry the enum.
  Status check_topics() {
    auto topics = sqlite::prepare(db.get(), "SELECT MIN(id), topic FROM outbox GROUP BY topic");
    if (!topics) return error("prepare");
    for (;;) {
      auto row = topics->step();
      if (!row) return error("read the topics");
      if (!*row) return Ok{};
      const auto* name = reinterpret_cast<const char*>(sqlite3_column_text(topics->get(), 1));
      if (!parse_topic_leaf(name ? name : ""))
        return Error{fmt::format("mqtt outbox {}: message {} has the topic \"{}\", which spinewatchd does not "
                                 "publish (summary, alert): a file of another program? Move it away, or give "
                                 "mqtt.outbox_path another file",
                                 path.string(), sqlite3_column_int64(topics->get(), 0), name ? name : "")};
    }
  }

  Error error(std::string_view what) const {
    return Error{fmt::format("mqtt outbox {}: {}: {}", path.string(), what, sqlite::message(db.get()))};
  }
};

MqttOutbox::MqttOutbox() : impl_(std::make_unique<Impl>()) {}
MqttOutbox::~MqttOutbox() = default;

Result<std::unique_ptr<MqttOutbox>> MqttOutbox::open(const std::filesystem::path& path, std::size_t max_messages) {
  std::unique_ptr<MqttOutbox> box(new MqttOutbox());
  Impl& d = *box->impl_;
  d.path = path;
  d.max_messages = max_messages == 0 ? 1 : max_messages;
  auto db = sqlite::open(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX);
  if (!db) return Error{fmt::format("mqtt outbox {}: {}", path.string(), db.error().message)};
  d.db = std::move(db).value();
  // WAL with synchronous = NORMAL: a commit is in the operating system's
  // hands when append() returns, so killing the daemon loses nothing; only
  // a power cut may lose the last commits (the cost of FULL, an fsync per
  // message, is not worth it for a summary a minute).
  for (const char* sql : {"PRAGMA journal_mode = WAL", "PRAGMA synchronous = NORMAL", "PRAGMA busy_timeout = 1000",
                          "CREATE TABLE IF NOT EXISTS outbox (id INTEGER PRIMARY KEY AUTOINCREMENT, "
                          "topic TEXT NOT NULL, payload TEXT NOT NULL)"})
    if (auto s = sqlite::exec(d.db.get(), sql); !s) return Error{fmt::format("mqtt outbox {}: {}", path.string(), s.error().message)};
  struct {
    sqlite::Statement* statement;
    const char* sql;
  } statements[] = {
      {&d.insert, "INSERT INTO outbox (topic, payload) VALUES (?, ?)"},
      {&d.drop, "DELETE FROM outbox WHERE id = (SELECT MIN(id) FROM outbox)"},
      {&d.select_after, "SELECT id, topic, payload FROM outbox WHERE id > ? ORDER BY id LIMIT ?"},
      {&d.remove, "DELETE FROM outbox WHERE id = ?"},
      {&d.count, "SELECT COUNT(*) FROM outbox"},
  };
  for (auto& s : statements) {
    auto prepared = sqlite::prepare(d.db.get(), s.sql);
    if (!prepared) return d.error("prepare");
    *s.statement = std::move(prepared).value();
  }
  if (auto s = d.check_topics(); !s) return s.error();
  auto row = d.count.step();
  if (!row) return d.error("count");
  box->size_ = static_cast<std::size_t>(sqlite3_column_int64(d.count.get(), 0));
  sqlite3_reset(d.count.get());
  return box;
}

Result<std::size_t> MqttOutbox::append(MqttTopic topic, const std::string& payload) {
  Impl& d = *impl_;
  std::size_t dropped = 0;
  for (; size_ >= d.max_messages; ++dropped, --size_)
    if (!d.drop.run()) return d.error("drop the oldest");
  if (!d.insert.bind(1, topic_leaf(topic)).bind(2, payload).run()) return d.error("append");
  ++size_;
  return dropped;
}

Result<std::vector<OutboxMessage>> MqttOutbox::after(std::int64_t after, std::size_t limit) {
  Impl& d = *impl_;
  std::vector<OutboxMessage> messages;
  d.select_after.bind(1, after).bind(2, static_cast<std::int64_t>(limit));
  for (;;) {
    auto row = d.select_after.step();
    if (!row) {
      sqlite3_reset(d.select_after.get());
      return d.error("read");
    }
    if (!*row) break;
    sqlite3_stmt* s = d.select_after.get();
    // open() checked the file's topics and append() writes only ours: a
    // name not ours now was written by another program meanwhile.
    const auto topic = parse_topic_leaf(reinterpret_cast<const char*>(sqlite3_column_text(s, 1)));
    if (!topic) {
      const std::int64_t id = sqlite3_column_int64(s, 0);
      sqlite3_reset(s);
      return Error{fmt::format("mqtt outbox {}: message {} has a topic spinewatchd does not publish", d.path.string(), id)};
    }
    messages.push_back({sqlite3_column_int64(s, 0), *topic, reinterpret_cast<const char*>(sqlite3_column_text(s, 2))});
  }
  sqlite3_reset(d.select_after.get());
  return messages;
}

Status MqttOutbox::remove(std::int64_t id) {
  Impl& d = *impl_;
  if (!d.remove.bind(1, id).run()) return d.error("remove");
  if (sqlite3_changes(d.db.get()) > 0 && size_ > 0) --size_;
  return Ok{};
}

}  // namespace spinewatch
