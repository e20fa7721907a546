// The host side of the trigger controller's line protocol
// (docs/trigger-protocol.md): a reply line as the controller (or a device
// that is not one) may send it, through the parsers of STATUS and VERSION.
#include "fuzz_support.hpp"
#include "spinewatch/sync/trigger_controller.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace spinewatch;
  const std::string_view line = fuzz::as_text(data, size);
  if (auto status = sync::parse_trigger_status(line)) {
    FUZZ_CHECK(line.substr(0, 3) == "OK ", "a STATUS reply without OK");
    FUZZ_CHECK(!sync::describe(*status).empty(), "an empty description");
  }
  if (auto version = sync::parse_trigger_version(line)) {
    FUZZ_CHECK(!version->firmware.empty() && version->firmware.find(' ') == std::string::npos, version->firmware);
  }
  return 0;
}
