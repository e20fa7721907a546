#include "spinewatch/daemon/client_command.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "spinewatch/frames/printable.hpp"

namespace spinewatch {
namespace {

using json = nlohmann::json;
using ojson = nlohmann::ordered_json;  // replies keep "class" first

constexpr int kReplyVersion = 1;

// The same bounds as the config keys subject.stature_mm and subject.mass_kg.
struct Bounds {
  const char* key;
  double min, max;
};
constexpr Bounds kStature{"stature_mm", 1000, 2300};
constexpr Bounds kMass{"mass_kg", 20, 250};

Result<std::optional<double>> optional_number(const json& j, const Bounds& b) {
  const auto it = j.find(b.key);
  if (it == j.end() || it->is_null()) return std::optional<double>{};
  if (!it->is_number()) return Error{fmt::format("{}: expected a number or null, got {}", b.key, it->type_name())};
  const double v = it->get<double>();
  if (!(v >= b.min && v <= b.max)) return Error{fmt::format("{}: {} is out of range [{}, {}]", b.key, v, b.min, b.max)};
  return std::optional<double>(v);
}

ojson worker_json(const KnownWorker& w) {
  return {{"stature_mm", w.stature_mm ? ojson(*w.stature_mm) : ojson(nullptr)},
          {"mass_kg", w.mass_kg ? ojson(*w.mass_kg) : ojson(nullptr)}};
}

}  // namespace

Result<SetWorkerCommand> parse_client_command(std::string_view line) {
  const json j = json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return Error{"not valid JSON (one JSON object per line)"};
  if (!j.is_object()) return Error{"not a JSON object"};
  const auto command = j.find("command");
  if (command == j.end()) return Error{"command: missing"};
  if (!command->is_string()) return Error{fmt::format("command: expected a string, got {}", command->type_name())};
  // What a client sent is quoted through printable(): the message goes to
  // the log, and a "\n" in a client's string must not forge a log line
  // (found by the client_command fuzzer).
  if (*command != "set_worker")
    return Error{fmt::format("command: \"{}\" is not a command (known: set_worker)",
                             printable(command->get<std::string>()))};
  for (const auto& [key, value] : j.items())
    if (key != "command" && key != kStature.key && key != kMass.key)
      return Error{fmt::format("{}: not a field of set_worker (stature_mm, mass_kg)", printable(key))};
  SetWorkerCommand c;
  auto stature = optional_number(j, kStature);
  if (!stature) return stature.error();
  auto mass = optional_number(j, kMass);
  if (!mass) return mass.error();
  c.worker = {*stature, *mass};
  return c;
}

std::string accepted_reply(const SetWorkerCommand& command) {
  return ojson{{"class", "reply"}, {"v", kReplyVersion}, {"command", "set_worker"},
              {"ok", true},       {"worker", worker_json(command.worker)}}
      .dump();
}

std::string rejected_reply(const Error& error) {
  return ojson{{"class", "reply"}, {"v", kReplyVersion}, {"ok", false}, {"error", error.message}}.dump();
}

}  // namespace spinewatch
