// A subject's spine file (`spinewatch deform --subject`, `fit-spine`;
// docs/spine-model.md) through parse_subject_json, the text half of its
// public loader load_subject_file. An accepted spine survives the round
// trip through subject_to_json (to the last bit of a renormalised
// quaternion: found by this harness, a unit quaternion normalised again
// may move in its last bit, so the text is not compared).
#include "fuzz_support.hpp"
#include "spinewatch/estimator/spine/subject.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spinewatch::fuzz::silence_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace spinewatch;
  constexpr std::string_view kSource = "subject.json";
  auto subject = parse_subject_json(fuzz::as_text(data, size), kSource);
  if (!subject) {
    fuzz::check_one_clear_message(subject.error().message, kSource);
    return 0;
  }
  const std::string written = subject_to_json(*subject);
  auto reread = parse_subject_json(written, "round trip");
  FUZZ_CHECK(reread.ok(), reread.ok() ? written : reread.error().message);
  // The same spine, up to the last bit a quaternion's renormalisation moves.
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    const SubjectVertebra &a = (*subject)[i], &b = (*reread)[i];
    const double scale = 1.0 + a.pose.body_center.norm();
    FUZZ_CHECK((a.pose.body_center - b.pose.body_center).norm() <= 1e-12 * scale, written);
    FUZZ_CHECK(a.pose.q.angularDistance(b.pose.q) <= 1e-9, written);
    FUZZ_CHECK(a.dims.height_mm == b.dims.height_mm && a.dims.width_mm == b.dims.width_mm &&
                   a.dims.depth_mm == b.dims.depth_mm,
               written);
  }
  return 0;
}
