// The targets file of `spinewatch deform` (docs/interfaces.md §4) through
// parse_target_lines: the input is the whole NDJSON text. Accepted lines
// are finite, their directions unit vectors.
#include "fuzz_support.hpp"
#include "spinewatch/estimator/spine/target_lines.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace spinewatch;
  constexpr std::string_view kName = "targets.ndjson";
  auto lines = parse_target_lines(fuzz::as_text(data, size), kName);
  if (!lines) {
    fuzz::check_one_clear_message(lines.error().message, kName);
    return 0;
  }
  FUZZ_CHECK(!lines->empty(), "an accepted file without lines");
  for (const TargetLine& t : *lines) {
    FUZZ_CHECK(t.targets.neck.allFinite() && t.targets.waist.allFinite(), "a non-finite target");
    for (const auto& dir : {t.targets.neck_dir, t.targets.waist_dir})
      FUZZ_CHECK(!dir || std::abs(dir->norm() - 1.0) < 1e-9, "a direction that is not unit");
  }
  return 0;
}
