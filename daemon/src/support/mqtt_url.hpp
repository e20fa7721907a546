#pragma once
// The pieces of [mqtt] that are pure text (docs/interfaces.md §7, docs/fleet.md):
// the broker's URL, the station's name made safe for a topic, and the
// reconnection back-off. In daemon support, where the configuration is
// parsed, so that a bad URL is refused with its key and line.
#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct MqttUrl {
  bool tls = false;        // mqtts://
  std::string host;        // a name, an IPv4 address, or an IPv6 address (given in brackets)
  std::uint16_t port = 0;  // 1–65535, always given: a broker's port is site policy, not ours to guess
  bool operator==(const MqttUrl&) const = default;
};

// "mqtt://HOST:PORT" or "mqtts://HOST:PORT" ("mqtt://[::1]:1883" for IPv6);
// anything else (another scheme, a path, user info, no port) is an error
// saying what is wrong.
Result<MqttUrl> parse_mqtt_url(std::string_view text);

// The station's name as one topic level: '+', '#' and '/' (the MQTT
// wildcards and the level separator), control characters and NUL become
// '_'; an empty name becomes "_". Everything else (UTF-8 included) is kept.
std::string topic_safe_station(std::string_view station);

// The wait before the next connection attempt after `failures` failed ones
// in a row (≥ 1): min_s, doubled each time, at most max_s.
std::chrono::milliseconds mqtt_reconnect_delay(int failures, double min_s, double max_s);

}  // namespace spinewatch
