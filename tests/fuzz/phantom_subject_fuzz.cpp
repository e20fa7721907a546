// A phantom subject file (config/subjects/*.json, docs/phantom.md) through
// its public loader, load_subject(path): the input is the file. An
// accepted subject survives the round trip recording.json makes of it
// (to_json, then parse_subject) unchanged.
#include <nlohmann/json.hpp>

#include "fuzz_support.hpp"
#include "spinewatch/phantom/subject.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace spinewatch;
  static const std::filesystem::path file = fuzz::scratch_dir() / "subject.json";
  fuzz::write_input(file, data, size);
  auto subject = phantom::load_subject(file);
  if (!subject) {
    fuzz::check_one_clear_message(subject.error().message, file.string());
    return 0;
  }
  const nlohmann::json written = phantom::to_json(*subject);
  auto reread = phantom::parse_subject(written, "round trip");
  FUZZ_CHECK(reread.ok(), reread.ok() ? "" : reread.error().message);
  FUZZ_CHECK(phantom::to_json(*reread) == written, written.dump());
  return 0;
}
