#include "ops/client_command.hpp"

#include <algorithm>
#include <cctype>
#include <iterator>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "spinewatch/frames/printable.hpp"

namespace spinewatch {
namespace {

using json = nlohmann::json;
using ojson = nlohmann::ordered_json;  // replies keep "class" first

constexpr int kReplyVersion = 1;

// The same bounds as the config keys subject.stature_mm, mass_kg,
// c7_height_mm and iliac_crest_height_mm.
struct Bounds {
  const char* key;
  double min, max;
};
constexpr Bounds kStature{"stature_mm", 1000, 2300};
constexpr Bounds kMass{"mass_kg", 20, 250};
constexpr Bounds kC7{"c7_height_mm", 800, 2000};
constexpr Bounds kCrest{"iliac_crest_height_mm", 500, 1400};
constexpr Bounds kFields[] = {kStature, kMass, kC7, kCrest};

Result<std::optional<double>> optional_number(const json& j, const Bounds& b) {
  const auto it = j.find(b.key);
  if (it == j.end() || it->is_null()) return std::optional<double>{};
  if (!it->is_number()) return Error{fmt::format("{}: expected a number or null, got {}", b.key, it->type_name())};
  const double v = it->get<double>();
  if (!(v >= b.min && v <= b.max)) return Error{fmt::format("{}: {} is out of range [{}, {}]", b.key, v, b.min, b.max)};
  return std::optional<double>(v);
}

ojson worker_json(const KnownWorker& w) {
  auto value = [](const std::optional<double>& v) { return v ? ojson(*v) : ojson(nullptr); };
  ojson j = {{"stature_mm", value(w.stature_mm)}, {"mass_kg", value(w.mass_kg)}};
  // The landmarks only when given: replies to clients that never send them
  // stay as they were.
  if (w.c7_height_mm) j["c7_height_mm"] = *w.c7_height_mm;
  if (w.iliac_crest_height_mm) j["iliac_crest_height_mm"] = *w.iliac_crest_height_mm;
  return j;
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
  // The key by name, not a structured binding: clang 14 (the fuzz
  // build) cannot capture a binding in a lambda.
  for (const auto& item : j.items()) {
    const std::string& key = item.key();
    if (key != "command" && key != "id" &&
        std::none_of(std::begin(kFields), std::end(kFields), [&](const Bounds& b) { return key == b.key; }))
      return Error{fmt::format(
          "{}: not a field of set_worker (stature_mm, mass_kg, c7_height_mm, iliac_crest_height_mm, id)", printable(key))};
  }
  SetWorkerCommand c;
  if (const auto id = j.find("id"); id != j.end() && !id->is_null()) {
    if (!id->is_string()) return Error{fmt::format("id: expected a string or null, got {}", id->type_name())};
    const std::string text = id->get<std::string>();
    const bool ok = !text.empty() && text.size() <= 64 &&
                    std::all_of(text.begin(), text.end(), [](char ch) {
                      return std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '_' || ch == '-';
                    });
    if (!ok) return Error{"id: 1 to 64 letters, digits, '.', '_' or '-'"};
    c.id = text;
  }
  std::optional<double>* fields[] = {&c.worker.stature_mm, &c.worker.mass_kg, &c.worker.c7_height_mm,
                                     &c.worker.iliac_crest_height_mm};
  for (std::size_t i = 0; i < std::size(kFields); ++i) {
    auto v = optional_number(j, kFields[i]);
    if (!v) return v.error();
    *fields[i] = *v;
  }
  if (const WorkerCheck check = check_known_worker(c.worker); !check.ok) return Error{check.message};
  return c;
}

std::string accepted_reply(const SetWorkerCommand& command) {
  ojson worker = worker_json(command.worker);
  if (command.id) worker["id"] = *command.id;
  return ojson{{"class", "reply"}, {"v", kReplyVersion}, {"command", "set_worker"}, {"ok", true}, {"worker", worker}}
      .dump();
}

std::string rejected_reply(const Error& error) {
  return ojson{{"class", "reply"}, {"v", kReplyVersion}, {"ok", false}, {"error", error.message}}.dump();
}

}  // namespace spinewatch
