#pragma once
// The commands a station's clients may send (docs/interfaces.md §5: what they
// send changes nothing unless a documented command says so;
// docs/protocol.md, "Commands"). One JSON object per line; the daemon
// answers the sender alone with a "reply" line.
#include <string>
#include <string_view>

#include "spinewatch/estimator/anatomy/worker.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// {"command": "set_worker", "stature_mm": 1755, "mass_kg": 80}: the worker
// now in view; a field left out or null is not known (measured or
// estimated). Starts the subject's model afresh. Optional "id": who it is
// (1–64 characters, letters, digits, '.', '_', '-'), carried by the
// exposure summaries and alerts from then on; a new worker starts a new
// shift (docs/exposure.md).
struct SetWorkerCommand {
  KnownWorker worker;
  std::optional<std::string> id;
};

// The command a line holds, or what is wrong with it (field and problem).
Result<SetWorkerCommand> parse_client_command(std::string_view line);

// {"class":"reply","v":1,"command":"set_worker","ok":true,"worker":{…}}
std::string accepted_reply(const SetWorkerCommand& command);
// {"class":"reply","v":1,"ok":false,"error":"…"}
std::string rejected_reply(const Error& error);

}  // namespace spinewatch
