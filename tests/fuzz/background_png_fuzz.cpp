// The station's empty scene (background_frontal.png / _lateral.png,
// docs/interfaces.md §2) through load_background_images, as the daemon, `replay`
// and `record` load it: the input is the image file, read as both views.
// A loaded scene must be packed rows of the size it says.
#include "fuzz_support.hpp"
#include "spinewatch/capture/background_images.hpp"

namespace {
void check_scene(const spinewatch::SceneImage& s) {
  FUZZ_CHECK(s.width > 0 && s.height > 0, "an empty scene");
  FUZZ_CHECK(s.step == 1 || (s.step == 2 && s.width % 2 == 0), "a step that is neither grey nor YUYV");
  FUZZ_CHECK(s.pixels.size() == std::size_t(s.width) * std::size_t(s.height) * std::size_t(s.step),
             "pixels do not fill width x height");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace spinewatch;
  static const std::filesystem::path file = fuzz::scratch_dir() / "background.png";
  fuzz::write_input(file, data, size);
  auto images = load_background_images(file, file);
  if (!images) {
    fuzz::check_one_clear_message(images.error().message, file.string());
    return 0;
  }
  check_scene(images->frontal);
  check_scene(images->lateral);
  FUZZ_CHECK(images->frontal.pixels == images->lateral.pixels, "one file read twice differs");
  return 0;
}
