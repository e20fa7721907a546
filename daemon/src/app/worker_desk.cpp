#include "app/worker_desk.hpp"

#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "ops/client_command.hpp"

namespace spinewatch {

namespace {

std::string describe(const KnownWorker& w) {
  std::string text = fmt::format("stature {}, mass {}", w.stature_mm ? fmt::format("{:.0f} mm", *w.stature_mm) : "not known",
                                 w.mass_kg ? fmt::format("{:.1f} kg", *w.mass_kg) : "not known");
  if (w.c7_height_mm) text += fmt::format(", C7 at {:.0f} mm", *w.c7_height_mm);
  if (w.iliac_crest_height_mm) text += fmt::format(", iliac crest at {:.0f} mm", *w.iliac_crest_height_mm);
  return text;
}

}  // namespace

Status WorkerDesk::open_explicit_secret() {
  if (!privacy_.pseudonymise || privacy_.secret_file.empty()) return Ok{};
  auto opened = Pseudonyms::open(privacy_.secret_file);
  if (!opened) return opened.error();
  pseudonyms_ = std::move(opened).value();
  return Ok{};
}

void WorkerDesk::set(const KnownWorker& worker, std::string_view by, std::optional<std::string> id) {
  spdlog::info("worker {}set by {}: {}; the subject's model is built afresh", id ? *id + " " : "", by,
               describe(worker));
  std::lock_guard lock(mutex_);
  pending_ = Handover{worker, std::move(id)};
}

std::optional<WorkerDesk::Handover> WorkerDesk::take() {
  std::lock_guard lock(mutex_);
  return std::exchange(pending_, std::nullopt);
}

ClientInputReply WorkerDesk::on_client_line(std::string_view line, const std::string& client) {
  if (line.find_first_not_of(" \t") == std::string_view::npos) return {};
  auto command = parse_client_command(line);
  if (!command) {
    spdlog::warn("client {}: {}", client, command.error().message);
    return {rejected_reply(command.error()), false};
  }
  if (command->id) {
    // From here on only the pseudonym exists: the store, the stream, the
    // log and the reply itself carry it (docs/security.md).
    auto named = worker_name(*command->id);
    if (!named) {
      spdlog::error("client {}: set_worker refused: {}", client, named.error().message);
      return {rejected_reply(Error{"id: " + named.error().message}), false};
    }
    command->id = std::move(named).value();
  }
  set(command->worker, "client " + client, command->id);
  return {accepted_reply(*command), true};
}

// The id as the station records it: its pseudonym unless privacy.pseudonymise = false.
Result<std::string> WorkerDesk::worker_name(const std::string& id) {
  if (!privacy_.pseudonymise) return id;
  if (!pseudonyms_) {
    auto path = privacy_.secret_file.empty() ? default_secret_path() : Result<std::filesystem::path>(privacy_.secret_file);
    if (!path) return path.error();
    auto opened = Pseudonyms::open(*path);
    if (!opened) return opened.error();
    pseudonyms_ = std::move(opened).value();
  }
  return pseudonyms_->of(id);
}

}  // namespace spinewatch
