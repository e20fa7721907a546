#include <sys/stat.h>

#include <cstdlib>
#include <fstream>

#include <fmt/format.h>

#include "mqtt/mqtt_publisher.hpp"
#include "spinewatch/frames/text_file.hpp"
#include "support/station_dirs.hpp"

namespace spinewatch {
namespace {

Status check_readable(const char* key, const std::string& path) {
  if (path.empty()) return Ok{};
  std::ifstream in(path);
  if (!in) return Error{fmt::format("mqtt.{}: {}: cannot be read", key, path)};
  return Ok{};
}

// A password in a file others can read is not a secret: refused, not warned.
Result<std::string> read_password(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return Error{fmt::format("mqtt.password_file: {}: cannot be read", path)};
  if ((st.st_mode & 077) != 0)
    return Error{fmt::format(
        "mqtt.password_file: {}: mode {:04o} lets group or others read it; `chmod 600 {}` (or give it with systemd's "
        "LoadCredential=, docs/fleet.md)",
        path, st.st_mode & 07777, path)};
  auto text = read_text_file(path);
  if (!text) return Error{"mqtt.password_file: " + text.error().message};
  std::string password = std::move(text).value();
  while (!password.empty() && (password.back() == '\n' || password.back() == '\r')) password.pop_back();
  if (password.empty()) return Error{fmt::format("mqtt.password_file: {}: empty", path)};
  if (password.find('\n') != std::string::npos)
    return Error{fmt::format("mqtt.password_file: {}: more than one line (the file holds the password alone)", path)};
  return password;
}

Result<std::filesystem::path> default_outbox_path() {
  return default_station_file(StationDir::State, "mqtt-outbox.db", "mqtt.outbox_path");
}

}  // namespace

Result<std::optional<MqttOptions>> mqtt_options(const Config& config) {
  const Config::Mqtt& m = config.mqtt;
  if (m.url.empty()) return std::optional<MqttOptions>{};
  auto url = parse_mqtt_url(m.url);
  if (!url) return Error{"mqtt.url: " + url.error().message};
  MqttOptions o;
  o.url = *url;
  o.station = config.station.name;
  if (auto s = check_readable("ca_file", m.ca_file); !s) return s.error();
  if (auto s = check_readable("cert_file", m.cert_file); !s) return s.error();
  if (auto s = check_readable("key_file", m.key_file); !s) return s.error();
  o.ca_file = m.ca_file;
  o.cert_file = m.cert_file;
  o.key_file = m.key_file;
  o.username = m.username;
  if (!m.password_file.empty()) {
    auto password = read_password(m.password_file);
    if (!password) return password.error();
    o.password = std::move(password).value();
  }
  o.posture_rate_hz = m.posture_rate_hz;
  o.qos = m.qos;
  if (m.outbox_path.empty()) {
    auto outbox = default_outbox_path();
    if (!outbox) return outbox.error();
    o.outbox_path = std::move(outbox).value();
  } else {
    o.outbox_path = m.outbox_path;
  }
  o.outbox_max_messages = static_cast<std::size_t>(m.outbox_max_messages);
  o.keepalive_s = m.keepalive_s;
  o.reconnect_min_s = m.reconnect_min_s;
  o.reconnect_max_s = m.reconnect_max_s;
  return std::optional<MqttOptions>(std::move(o));
}

}  // namespace spinewatch
