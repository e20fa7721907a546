// spinewatch background: the station's empty scene, from its two cameras
// or from the empty frames of a recording, into background_frontal.png and
// background_lateral.png (docs/interfaces.md §2; docs/tuning.md, "Background").
// The per-pixel median of the frames taken, refused when the scene moved
// while they were taken (someone in view): a background with a person in
// it would hide that person for as long as the station runs.
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/capture/background_images.hpp"
#include "spinewatch/capture/recording.hpp"
#include "spinewatch/capture/v4l2_camera.hpp"
#include "spinewatch/daemon/camera_pair_source.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/estimator/silhouette/background_bootstrap.hpp"

namespace spinewatch::cli {
namespace {

struct BackgroundOptions {
  std::string out, recording, config, frontal, lateral;
  int from = 0;
  int frames = 30;
  std::optional<int> threshold;
  std::optional<int> max_moved_px;
};

// The mean chroma of YUYV frames (the luma's median is the bootstrap's):
// the scene was still, so the mean is its colour. Empty when a frame was grey.
class ChromaMean {
 public:
  void add(const LumaView& frame) {
    if (frame.step != 2 || frame.width % 2 != 0) {
      grey_ = true;
      return;
    }
    const std::size_t n = static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height);
    if (sum_.size() != n) sum_.assign(n, 0);
    for (int y = 0; y < frame.height; ++y)
      for (int x = 0; x < frame.width; ++x)
        sum_[static_cast<std::size_t>(y * frame.width + x)] += frame.row(y)[2 * x + 1];
    ++count_;
  }
  // YUYV bytes from `luma` and this mean; nothing when there is no colour.
  std::optional<std::vector<std::uint8_t>> yuyv(const std::vector<std::uint8_t>& luma) const {
    if (grey_ || count_ == 0 || sum_.size() != luma.size()) return std::nullopt;
    std::vector<std::uint8_t> out(2 * luma.size());
    for (std::size_t i = 0; i < luma.size(); ++i) {
      out[2 * i] = luma[i];
      out[2 * i + 1] = static_cast<std::uint8_t>((sum_[i] + count_ / 2) / count_);
    }
    return out;
  }

 private:
  std::vector<std::uint32_t> sum_;
  std::uint32_t count_ = 0;
  bool grey_ = false;
};

// Both views' frames, collected into one sample window each.
struct SceneCapture {
  BackgroundBootstrap views[2];
  ChromaMean chroma[2];
  explicit SceneCapture(int frames, int threshold)
      : views{BackgroundBootstrap({.threshold = threshold, .sample_every = 1, .window_samples = frames}),
              BackgroundBootstrap({.threshold = threshold, .sample_every = 1, .window_samples = frames})} {}
  void add(int view, const LumaView& frame) {
    views[view].add(frame);
    chroma[view].add(frame);
  }
};

Status from_recording(const BackgroundOptions& o, SceneCapture& capture) {
  auto reader = RecordingReader::open(o.recording);
  if (!reader) return reader.error();
  for (int v = 0; v < 2; ++v) {
    const View view = static_cast<View>(v);
    const std::size_t have = reader->frame_count(view);
    if (static_cast<std::size_t>(o.from) + static_cast<std::size_t>(o.frames) > have)
      return Error{fmt::format("{}: --from {} --frames {} needs {} {} frames, the recording has {}", o.recording,
                               o.from, o.frames, o.from + o.frames, to_string(view), have)};
    for (int i = o.from; i < o.from + o.frames; ++i) {
      auto frame = reader->read(view, static_cast<std::size_t>(i));
      if (!frame) return frame.error();
      capture.add(v, frame->luma());
    }
  }
  return Ok{};
}

Status from_cameras(const BackgroundOptions& o, const Config& config, SceneCapture& capture) {
  // The cameras as the daemon opens them, on the devices given here if any.
  const CameraPairOptions pair = camera_pair_options(config);
  V4l2CameraOptions views[2] = {pair.frontal, pair.lateral};
  if (!o.frontal.empty()) views[0].path = o.frontal;
  if (!o.lateral.empty()) views[1].path = o.lateral;
  for (int v = 0; v < 2; ++v) {
    V4l2Camera camera(views[v]);
    if (auto s = camera.start(); !s) return s.error();
    for (int i = 0; i < o.frames; ++i) {
      auto frame = camera.next(std::chrono::milliseconds(2000));
      if (!frame) return Error{fmt::format("{} ({}): no frame within 2 s", views[v].name, views[v].path)};
      capture.add(v, frame->luma());
    }
    camera.stop();
  }
  return Ok{};
}

int run(const BackgroundOptions& o, ExitCode& exit_code) {
  Config config;
  if (!o.config.empty()) {
    auto loaded = load_config(o.config);
    if (!loaded) {
      exit_code.fail(loaded.error());
      return exit_code.value;
    }
    config = std::move(loaded).value();
  }
  const int threshold = o.threshold.value_or(config.silhouette.threshold);
  // Movement smaller than a quarter of the smallest person blob is noise
  // or a flickering light, not someone in view.
  const int max_moved = o.max_moved_px.value_or(config.silhouette.min_blob_px / 4);
  SceneCapture capture(o.frames, threshold);
  const Status taken = o.recording.empty() ? from_cameras(o, config, capture) : from_recording(o, capture);
  if (!taken) {
    exit_code.fail(taken.error());
    return exit_code.value;
  }
  BackgroundImages images;
  SceneImage* out[2] = {&images.frontal, &images.lateral};
  const char* names[2] = {"frontal", "lateral"};
  for (int v = 0; v < 2; ++v) {
    const BackgroundBootstrap& b = capture.views[v];
    const std::int64_t moved = b.moved_px();
    if (moved > max_moved) {
      exit_code.fail(Error{fmt::format(
          "{}: {} pixels changed by more than {} grey levels over the {} frames (at most {} allowed): the scene "
          "was not empty or not still. Clear the view{} and try again",
          names[v], moved, threshold, o.frames, max_moved,
          o.recording.empty() ? "" : ", or pick empty frames of the recording with --from/--frames")});
      return exit_code.value;
    }
    std::vector<std::uint8_t> luma = b.median();
    if (auto colour = capture.chroma[v].yuyv(luma))
      *out[v] = SceneImage{b.width(), b.height(), 2, std::move(*colour)};
    else
      *out[v] = SceneImage{b.width(), b.height(), 1, std::move(luma)};
    spdlog::info("{}: median of {} frames, {} pixels moved{}", names[v], b.samples(), moved,
                 out[v]->colour() ? ", with colour" : "");
  }
  if (auto s = write_background_images(o.out, images); !s) {
    exit_code.fail(s.error());
    return exit_code.value;
  }
  const std::filesystem::path dir = std::filesystem::absolute(o.out);
  fmt::print("wrote {} and {}\nuse them with, in the station's configuration:\n  [silhouette]\n  background_frontal = \"{}\"\n"
             "  background_lateral = \"{}\"\n",
             (dir / kBackgroundFiles[0]).string(), (dir / kBackgroundFiles[1]).string(),
             (dir / kBackgroundFiles[0]).string(), (dir / kBackgroundFiles[1]).string());
  return 0;
}

}  // namespace

void add_background_command(CLI::App& app, ExitCode& exit_code) {
  auto opts = std::make_shared<BackgroundOptions>();
  auto* cmd = app.add_subcommand("background", "Capture the empty scene into background_frontal.png / background_lateral.png");
  cmd->add_option("--out", opts->out, "directory to write the two PNGs into")->required();
  cmd->add_option("--recording", opts->recording, "take the frames from this recording instead of the cameras");
  cmd->add_option("--from", opts->from, "first frame of the recording to use")->check(CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--frames", opts->frames, "frames per camera to take the median of")->check(CLI::Range(3, 300))->capture_default_str();
  cmd->add_option("--config", opts->config, "the station's TOML configuration (cameras, threshold; default: built-in defaults)");
  cmd->add_option("--frontal", opts->frontal, "frontal camera device (default: cameras.frontal)");
  cmd->add_option("--lateral", opts->lateral, "lateral camera device (default: cameras.lateral)");
  cmd->add_option("--threshold", opts->threshold, "grey levels of change that count as movement (default: silhouette.threshold)")
      ->check(CLI::Range(1, 254));
  cmd->add_option("--max-moved", opts->max_moved_px, "pixels allowed to change (default: silhouette.min_blob_px / 4)")
      ->check(CLI::NonNegativeNumber);
  cmd->footer("Clear the cameras' view (nobody in it) and keep the lights as they are in use.\n");
  cmd->callback([opts, &exit_code] { run(*opts, exit_code); });
}

}  // namespace spinewatch::cli
