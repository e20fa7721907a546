#include "support/mqtt_url.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "spinewatch/frames/printable.hpp"

namespace spinewatch {

Result<MqttUrl> parse_mqtt_url(std::string_view text) {
  MqttUrl url;
  std::string_view rest;
  if (text.rfind("mqtt://", 0) == 0) {
    rest = text.substr(7);
  } else if (text.rfind("mqtts://", 0) == 0) {
    url.tls = true;
    rest = text.substr(8);
  } else {
    return Error{fmt::format("\"{}\": expected mqtt://HOST:PORT or mqtts://HOST:PORT (or \"\" for off)", printable(text))};
  }
  const auto bad = [&](std::string_view why) {
    return Error{fmt::format("\"{}\": {} (expected {}://HOST:PORT)", printable(text), why, url.tls ? "mqtts" : "mqtt")};
  };
  if (rest.find_first_of("/?#@ \t") != std::string_view::npos)
    return bad("a path, query, user info or space is not allowed (credentials go in username and password_file)");
  std::string_view port;
  if (!rest.empty() && rest.front() == '[') {
    const auto close = rest.find(']');
    if (close == std::string_view::npos) return bad("an IPv6 address without its closing ']'");
    url.host = std::string(rest.substr(1, close - 1));
    if (close + 1 >= rest.size() || rest[close + 1] != ':') return bad("no port");
    port = rest.substr(close + 2);
  } else {
    const auto colon = rest.rfind(':');
    if (colon == std::string_view::npos) return bad("no port");
    url.host = std::string(rest.substr(0, colon));
    if (url.host.find(':') != std::string::npos) return bad("an IPv6 address must be in brackets");
    port = rest.substr(colon + 1);
  }
  if (url.host.empty()) return bad("no host");
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (port.empty() || ec != std::errc{} || end != port.data() + port.size() || value < 1 || value > 65535)
    return bad("the port must be a number in [1, 65535]");
  url.port = static_cast<std::uint16_t>(value);
  return url;
}

std::string topic_safe_station(std::string_view station) {
  std::string safe(station);
  for (char& c : safe)
    if (c == '+' || c == '#' || c == '/' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '_';
  return safe.empty() ? "_" : safe;
}

std::chrono::milliseconds mqtt_reconnect_delay(int failures, double min_s, double max_s) {
  const double s = min_s * std::pow(2.0, std::clamp(failures, 1, 40) - 1);
  return std::chrono::milliseconds(static_cast<std::int64_t>(std::min(s, max_s) * 1000.0));
}

}  // namespace spinewatch
