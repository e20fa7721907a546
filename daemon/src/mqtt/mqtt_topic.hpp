#pragma once
// The topics the station publishes under spinewatch/<station>/
// (docs/interfaces.md §7). The code holds the enum; only the broker and the
// outbox file see the names, which are spelt here alone.
#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace spinewatch {

enum class MqttTopic : std::uint8_t {
  Status,   // retained "online"; "offline" as the last will
  Posture,  // posture lines, at most mqtt.posture_rate_hz
  Summary,  // summary lines, QoS 1, through the outbox
  Alert,    // alert lines, QoS 1, through the outbox
};

// The topic's last level: "status", "posture", "summary", "alert".
constexpr std::string_view topic_leaf(MqttTopic topic) {
  switch (topic) {
    case MqttTopic::Status: return "status";
    case MqttTopic::Posture: return "posture";
    case MqttTopic::Summary: return "summary";
    case MqttTopic::Alert: return "alert";
  }
  return "?";
}

// The topic a last level names (what the outbox file holds), or nothing.
constexpr std::optional<MqttTopic> parse_topic_leaf(std::string_view leaf) {
  for (MqttTopic t : std::array{MqttTopic::Status, MqttTopic::Posture, MqttTopic::Summary, MqttTopic::Alert})
    if (topic_leaf(t) == leaf) return t;
  return std::nullopt;
}

}  // namespace spinewatch
