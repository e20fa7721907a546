// Parsing the controller's OK lines (docs/trigger-protocol.md).
#include <charconv>
#include <map>

#include <fmt/format.h>

#include "spinewatch/sync/trigger_controller.hpp"

namespace spinewatch::sync {

namespace {

std::string_view strip_ok(std::string_view reply) {
  if (reply.substr(0, 3) == "OK ") return reply.substr(3);
  return {};
}

std::map<std::string_view, std::string_view> fields(std::string_view text) {
  std::map<std::string_view, std::string_view> out;
  while (!text.empty()) {
    const auto space = text.find(' ');
    const std::string_view token = text.substr(0, space);
    const auto eq = token.find('=');
    if (eq != std::string_view::npos) out[token.substr(0, eq)] = token.substr(eq + 1);
    if (space == std::string_view::npos) break;
    text.remove_prefix(space + 1);
  }
  return out;
}

template <class T>
bool parse_number(std::string_view text, T& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc{} && end == text.data() + text.size();
}

}  // namespace

Result<TriggerControllerStatus> parse_trigger_status(std::string_view reply) {
  const auto f = fields(strip_ok(reply));
  TriggerControllerStatus s;
  int running = -1;
  const auto need = [&](std::string_view key, auto& out) {
    const auto it = f.find(key);
    return it != f.end() && parse_number(it->second, out);
  };
  if (!need("rate", s.rate_hz) || !need("width", s.width_us) || !need("delay_a", s.delay_a_us) ||
      !need("delay_b", s.delay_b_us) || !need("running", running) || !need("count", s.count) ||
      !need("uptime_ms", s.uptime_ms) || (running != 0 && running != 1))
    return Error{fmt::format("not a STATUS reply: '{}'", reply)};
  s.running = running == 1;
  return s;
}

Result<TriggerControllerVersion> parse_trigger_version(std::string_view reply) {
  // "OK spinewatch-trigger 1.0.0 proto=1"
  constexpr std::string_view kName = "spinewatch-trigger ";
  std::string_view rest = strip_ok(reply);
  if (rest.substr(0, kName.size()) != kName) return Error{fmt::format("not a spinewatch trigger controller: '{}'", reply)};
  rest.remove_prefix(kName.size());
  TriggerControllerVersion v;
  v.firmware = std::string(rest.substr(0, rest.find(' ')));
  const auto f = fields(rest);
  const auto proto = f.find("proto");
  if (v.firmware.empty() || proto == f.end() || !parse_number(proto->second, v.protocol))
    return Error{fmt::format("not a VERSION reply: '{}'", reply)};
  return v;
}

std::string describe(const TriggerControllerStatus& s) {
  std::string text = fmt::format("{:.3f} Hz, {} us", s.rate_hz, s.width_us);
  if (s.delay_a_us || s.delay_b_us) text += fmt::format(", delays {}/{} us", s.delay_a_us, s.delay_b_us);
  text += fmt::format(", {}, {} pulses, up {} s", s.running ? "running" : "stopped", s.count, s.uptime_ms / 1000);
  return text;
}

}  // namespace spinewatch::sync
