// The daemon's configuration (docs/interfaces.md §6) through parse_config, the
// function load_config and the reload on SIGHUP both use: the input is
// the TOML text. A rejected file is one message naming the source.
#include "fuzz_support.hpp"
#include "spinewatch/daemon/config.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spinewatch::fuzz::silence_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace spinewatch;
  constexpr std::string_view kSource = "fuzz.toml";
  auto config = parse_config(fuzz::as_text(data, size), kSource);
  if (!config) {
    fuzz::check_one_clear_message(config.error().message, kSource);
    return 0;
  }
  // What a parse accepts, the defaults-plus-keys it describes: a second
  // parse of the same text gives the same configuration.
  auto again = parse_config(fuzz::as_text(data, size), kSource);
  FUZZ_CHECK(again.ok() && *again == *config, "the same text parsed twice differs");
  return 0;
}
