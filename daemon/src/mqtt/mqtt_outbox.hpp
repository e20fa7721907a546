#pragma once
// The MQTT publisher's persistent outbox (docs/fleet.md, "When the network
// is down"): the summary and alert messages the broker has not yet
// acknowledged, in an SQLite file, oldest first. A message leaves it only
// when the broker has acknowledged it (PUBACK), so one appended before a
// SIGKILL, a power cut of the broker or a daemon restart is still sent
// afterwards: at-least-once delivery. Bounded: appending to a full outbox
// drops its oldest message, and says so.
// Not thread-safe: the MQTT publisher's thread is its only user.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "mqtt/mqtt_topic.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct OutboxMessage {
  std::int64_t id = 0;   // increasing in the order appended
  MqttTopic topic = MqttTopic::Summary;  // stored as its last level (topic_leaf)
  std::string payload;
};

class MqttOutbox {
 public:
  // Opens (creating) the file; what it holds is kept. A file holding a
  // message under a topic this daemon does not publish (a file of another
  // program or version) is refused, naming the message.
  static Result<std::unique_ptr<MqttOutbox>> open(const std::filesystem::path& path, std::size_t max_messages);
  ~MqttOutbox();
  MqttOutbox(const MqttOutbox&) = delete;
  MqttOutbox& operator=(const MqttOutbox&) = delete;

  // Appends (committed before it returns); the number of oldest messages
  // dropped to keep within max_messages.
  Result<std::size_t> append(MqttTopic topic, const std::string& payload);
  // Up to `limit` messages with an id above `after`, oldest first.
  Result<std::vector<OutboxMessage>> after(std::int64_t after, std::size_t limit);
  // The broker has it: gone for good (an id already gone is no error).
  Status remove(std::int64_t id);
  std::size_t size() const { return size_; }

 private:
  MqttOutbox();
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::size_t size_ = 0;
};

}  // namespace spinewatch
