// recording.json as `spinewatch replay`, `eval` and the daemon read it
// (RecordingReader::open): the input is the file's text, in a directory
// whose frontal.raw and lateral.raw hold kRawBytes each, so the declared
// format and frame lists meet real files. An opened recording must read
// back every frame it says it has.
#include <fstream>
#include <vector>

#include "fuzz_support.hpp"
#include "spinewatch/capture/recording.hpp"

namespace {

namespace fs = std::filesystem;
using namespace spinewatch;

constexpr std::size_t kRawBytes = 96;  // 3 YUYV 4x4 frames, 12 GREY 4x2 frames, ...

const fs::path& recording_dir() {
  static const fs::path dir = [] {
    const fs::path d = fuzz::scratch_dir() / "rec";
    fs::create_directories(d);
    std::vector<std::uint8_t> bytes(kRawBytes);
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<std::uint8_t>(i);
    for (const char* name : {"frontal.raw", "lateral.raw"}) fuzz::write_input(d / name, bytes.data(), bytes.size());
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::silence_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path& dir = recording_dir();
  fuzz::write_input(dir / "recording.json", data, size);
  auto reader = RecordingReader::open(dir);
  if (!reader) {
    fuzz::check_one_clear_message(reader.error().message, dir.string());
    return 0;
  }
  const auto& info = reader->info();
  FUZZ_CHECK(info.fps > 0 && info.fps <= 1000, "fps out of the documented range");
  const std::size_t frame_bytes = info.format.frame_bytes();
  FUZZ_CHECK(frame_bytes > 0, "a zero-byte frame format");
  for (View view : kViews) {
    const std::size_t count = reader->frame_count(view);
    FUZZ_CHECK(count * frame_bytes <= kRawBytes, "more frames than the .raw file holds");
    for (std::size_t i = 0; i < count; ++i) {
      auto frame = reader->read(view, i);
      FUZZ_CHECK(frame.ok(), frame.ok() ? "" : frame.error().message);
      FUZZ_CHECK(frame->bytes().size() == frame_bytes, "a frame of the wrong size");
      FUZZ_CHECK(frame->info().sequence == info.frames[static_cast<int>(view)][i].sequence, "sequence changed");
    }
    auto past = reader->read(view, count);
    FUZZ_CHECK(!past.ok(), "a frame past the end");
    fuzz::check_one_clear_message(past.error().message, dir.string());
  }
  return 0;
}
