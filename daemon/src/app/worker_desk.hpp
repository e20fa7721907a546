#pragma once
// Who is being measured: the worker a client's set_worker or a reload
// names, handed from the thread that hears of it (the network loop's
// thread, the control thread) to the estimator thread, which takes it up
// before its next pair. Ids become pseudonyms here, before anything
// stores, publishes or logs them (privacy.pseudonymise, docs/security.md).
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "access/pseudonym.hpp"
#include "publish/publisher.hpp"
#include "spinewatch/daemon/config.hpp"

namespace spinewatch {

class WorkerDesk {
 public:
  explicit WorkerDesk(Config::Privacy privacy) : privacy_(std::move(privacy)) {}
  // A secret file set explicitly is checked at start (created if absent);
  // the default one at the first worker id, so a station that names no
  // worker needs no state directory.
  Status open_explicit_secret();

  // The network loop's thread: one line a publisher's client sent.
  ClientInputReply on_client_line(std::string_view line, const std::string& client);
  // Any thread: `worker` measures from the next pair on; `by` for the log.
  void set(const KnownWorker& worker, std::string_view by, std::optional<std::string> id = std::nullopt);

  struct Handover {
    KnownWorker worker;
    std::optional<std::string> id;  // the pseudonym (or id) it came with
  };
  // The estimator thread, before each pair.
  std::optional<Handover> take();

 private:
  Result<std::string> worker_name(const std::string& id);  // I/O thread

  const Config::Privacy privacy_;
  std::optional<Pseudonyms> pseudonyms_;  // I/O thread after start; opened at start or at the first id
  std::mutex mutex_;
  std::optional<Handover> pending_;
};

}  // namespace spinewatch
