// spinewatch record: both cameras (V4L2) into a recording directory with
// the driver's sequence numbers and timestamps, and the calibration in use.
#include <pthread.h>
#include <signal.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/capture/background_images.hpp"
#include "spinewatch/capture/recorder.hpp"
#include "spinewatch/capture/recording.hpp"
#include "spinewatch/capture/v4l2_camera.hpp"
#include "spinewatch/daemon/camera_pair_source.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/sync/frame_pairer.hpp"
#include "spinewatch/sync/trigger_source.hpp"

namespace spinewatch::cli {
namespace {

struct RecordOptions {
  std::string out;
  std::string frontal;
  std::string lateral;
  std::string config;
  std::optional<std::uint64_t> frames;
  std::optional<double> seconds;
};

// SIGINT/SIGTERM end the recording cleanly: a thread waits for them (they
// are blocked everywhere else) and stops the cameras.
class StopOnSignal {
 public:
  explicit StopOnSignal(std::function<void()> on_signal) : on_signal_(std::move(on_signal)) {
    sigemptyset(&set_);
    sigaddset(&set_, SIGINT);
    sigaddset(&set_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set_, &old_);
    thread_ = std::thread([this] {
      const timespec poll{0, 50'000'000};
      while (!done_.load()) {
        if (sigtimedwait(&set_, nullptr, &poll) > 0) {
          spdlog::info("record: stopping on signal");
          on_signal_();
        }
      }
    });
  }
  ~StopOnSignal() {
    done_.store(true);
    thread_.join();
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;

 private:
  std::function<void()> on_signal_;
  sigset_t set_{}, old_{};
  std::atomic<bool> done_{false};
  std::thread thread_;
};

// The station's stored background goes with the recording (docs/interfaces.md
// §2), so that replay sees the scene as the station did. Read before
// recording: a bad file is reported before the cameras start, not after.
Result<std::optional<BackgroundImages>> station_background(const Config& config) {
  const auto& s = config.silhouette;
  if (s.background_frontal.empty() && s.background_lateral.empty()) return std::optional<BackgroundImages>{};
  auto images = load_background_images(s.background_frontal, s.background_lateral, config.cameras.width,
                                       config.cameras.height);
  if (!images) return Error{"silhouette.background_frontal/_lateral: " + images.error().message};
  return std::optional<BackgroundImages>(std::move(images).value());
}

int record(const RecordOptions& opts) {
  Config config;
  if (!opts.config.empty()) {
    auto loaded = load_config(opts.config);
    if (!loaded) {
      spdlog::error("{}", loaded.error().message);
      return 1;
    }
    config = std::move(loaded.value());
  }
  auto background = station_background(config);
  if (!background) {
    spdlog::error("{}", background.error().message);
    return 1;
  }
  // The daemon's mapping of [cameras], with the devices the command line names.
  const CameraPairOptions pair = camera_pair_options(config);
  V4l2CameraOptions options[2] = {pair.frontal, pair.lateral};
  if (!opts.frontal.empty()) options[0].path = opts.frontal;
  if (!opts.lateral.empty()) options[1].path = opts.lateral;
  const std::string paths[2] = {options[0].path, options[1].path};
  std::unique_ptr<V4l2Camera> cameras[2];
  for (int v = 0; v < 2; ++v) {
    cameras[v] = std::make_unique<V4l2Camera>(options[v]);
    if (auto started = cameras[v]->start(); !started) {
      spdlog::error("{}", started.error().message);
      return 1;
    }
  }
  CameraRig rig = CameraRig::default_rig();
  const std::filesystem::path calibration = config.cameras.calibration;
  if (std::filesystem::exists(calibration)) {
    auto loaded = load_calibration(calibration);
    if (!loaded) {
      spdlog::error("{}", loaded.error().message);
      return 1;
    }
    if (auto s = check_image_size(*loaded, config.cameras.width, config.cameras.height); !s) {
      spdlog::error("{}: {}", calibration.string(), s.error().message);
      return 1;
    }
    rig = loaded.value();
  } else {
    spdlog::warn("{} not found: the recording gets the default rig (two ideal orthogonal cameras)",
                 calibration.string());
  }

  // Pairing runs alongside only to report how the streams will pair on replay.
  std::mutex mutex;  // pairer: frames come from the recorder's threads, edges from the trigger's
  sync::PairerOptions pairing = pairer_options(pair);
  pairing.fps = cameras[0]->fps();  // what the driver granted
  sync::FramePairer pairer(pairing);
  RecorderOptions recorder_options;
  recorder_options.frames = opts.frames;
  recorder_options.seconds = opts.seconds;
  recorder_options.notes = fmt::format("spinewatch record: frontal {}, lateral {}", paths[0], paths[1]);
  recorder_options.write_calibration = [&rig](const std::filesystem::path& path) { return save_calibration(path, rig); };
  recorder_options.on_frame = [&](View view, const Frame& frame) {
    std::lock_guard lock(mutex);
    // A copy: a frame waiting in the pairer must not hold the driver's buffer.
    pairer.push(view, Frame::copy_of(frame.format(), frame.info(), frame.bytes()));
    while (pairer.pop()) {
    }
  };
  Recorder recorder(*cameras[0], *cameras[1], std::move(recorder_options));
  // Before any thread starts, so that every thread inherits the blocked signals.
  StopOnSignal on_signal([&recorder] { recorder.stop(); });

  sync::TriggerSourceOptions trigger_options = pair.trigger;
  trigger_options.consumer = "spinewatch-record";
  auto trigger = sync::TriggerSource::open(trigger_options, [&](std::int64_t t) {
    std::lock_guard lock(mutex);
    pairer.push_trigger(t);
    while (pairer.pop()) {
    }
  });
  if (!trigger) {
    spdlog::error("{}", trigger.error().message);
    return 1;
  }

  auto recorded = recorder.record(opts.out);
  if (*trigger) (*trigger)->stop();
  pairer.flush();
  if (!recorded) {
    spdlog::error("{}", recorded.error().message);
    return 1;
  }
  for (int v = 0; v < 2; ++v) {
    const auto& c = recorded->counters[v];
    spdlog::info("{}: {} frames written; dropped {} error, {} sequence gaps; {} restarts", to_string(kViews[v]),
                 recorded->written[v], c.dropped_error, c.dropped_gap, c.restarts);
  }
  spdlog::info("pairing: {}", pairer.stats().summary());
  if (*background) {
    if (auto s = write_background_images(opts.out, **background); !s) {
      spdlog::error("{}", s.error().message);
      return 1;
    }
    spdlog::info("background: the station's copied into {}", opts.out);
  }
  spdlog::info("recorded to {}", opts.out);
  return 0;
}

}  // namespace

void add_record_command(CLI::App& app, ExitCode& exit_code) {
  auto opts = std::make_shared<RecordOptions>();
  auto* cmd = app.add_subcommand("record", "Record both cameras into a recording directory");
  cmd->add_option("--out", opts->out, "recording directory to create")->required();
  cmd->add_option("--frontal", opts->frontal, "frontal camera device (default: cameras.frontal)");
  cmd->add_option("--lateral", opts->lateral, "lateral camera device (default: cameras.lateral)");
  cmd->add_option("--config", opts->config, "TOML configuration (default: built-in defaults)");
  auto* frames = cmd->add_option("--frames", opts->frames, "stop after N frames from each camera")->check(CLI::PositiveNumber);
  auto* seconds = cmd->add_option("--seconds", opts->seconds, "stop after S seconds")->check(CLI::PositiveNumber);
  frames->excludes(seconds);
  cmd->footer("Without --frames or --seconds, records until SIGINT (Ctrl-C) or SIGTERM.\n");
  cmd->callback([opts, &exit_code] { exit_code.value = record(*opts); });
}

}  // namespace spinewatch::cli
