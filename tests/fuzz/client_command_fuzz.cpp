// A client's command line (docs/protocol.md, "Commands") through
// parse_client_command, and the reply the daemon sends back: whatever the
// line, the reply is one line of JSON with the reply fields.
#include <nlohmann/json.hpp>

#include "fuzz_support.hpp"
#include "ops/client_command.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace spinewatch;
  auto command = parse_client_command(fuzz::as_text(data, size));
  std::string reply;
  if (command) {
    FUZZ_CHECK(!command->worker.stature_mm || (*command->worker.stature_mm >= 1000 && *command->worker.stature_mm <= 2300),
               "stature out of range accepted");
    FUZZ_CHECK(!command->worker.mass_kg || (*command->worker.mass_kg >= 20 && *command->worker.mass_kg <= 250),
               "mass out of range accepted");
    reply = accepted_reply(*command);
  } else {
    fuzz::check_one_clear_message(command.error().message, "");
    reply = rejected_reply(command.error());
  }
  FUZZ_CHECK(reply.find('\n') == std::string::npos, reply);
  const auto j = nlohmann::json::parse(reply, nullptr, /*allow_exceptions=*/false);
  FUZZ_CHECK(j.is_object(), reply);
  FUZZ_CHECK(j.value("class", "") == "reply" && j.value("v", 0) == 1, reply);
  FUZZ_CHECK(j.contains("ok") && j["ok"].is_boolean() && j["ok"].get<bool>() == command.ok(), reply);
  return 0;
}
