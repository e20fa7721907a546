// A posture line (docs/interfaces.md §3) as `spinewatch eval` reads ground
// truth and recorded streams: decode_posture on the input. A decoded
// posture encodes to a line that decodes to the same line again.
#include "fuzz_support.hpp"
#include "spinewatch/estimator/posture_json.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace spinewatch;
  constexpr std::string_view kWhere = "postures.ndjson:1";
  auto posture = decode_posture(fuzz::as_text(data, size), kWhere);
  if (!posture) {
    fuzz::check_one_clear_message(posture.error().message, kWhere);
    return 0;
  }
  const std::string line = encode_posture(*posture);
  FUZZ_CHECK(line.find('\n') == std::string::npos, line);
  auto again = decode_posture(line, "re-encoded");
  FUZZ_CHECK(again.ok(), again.ok() ? line : again.error().message + " in " + line);
  FUZZ_CHECK(encode_posture(*again) == line, line);
  return 0;
}
