// spinewatch calibrate: the station's calibration.yaml from two recordings
// of a calibration board — held at poses in front of each camera (the
// intrinsics views) and placed where the subject will stand (the world
// frame) — with a report, refused when it would not hold
// (docs/calibration.md). With --live, the views and the placement come
// straight from both cameras instead of recordings.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>
#include <opencv2/core.hpp>
#include <spdlog/spdlog.h>

#include "calibrate_from.hpp"
#include "command.hpp"
#include "spinewatch/calibrate/grey_image.hpp"
#include "spinewatch/calibrate/live_session.hpp"
#include "spinewatch/calibrate/video_frames.hpp"
#include "spinewatch/capture/recording.hpp"
#include "spinewatch/capture/v4l2_camera.hpp"
#include "spinewatch/daemon/camera_pair_source.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/estimator/calibration/station_calibration.hpp"
#include "spinewatch/media/media_files.hpp"

namespace spinewatch::cli {
namespace {

constexpr const char* kCameraNames[2] = {"frontal", "lateral"};

struct Frames {
  std::array<std::vector<cv::Mat>, 2> grey;
  cv::Size size;
};

// The frames of both views of a recording that were taken together, as
// grey images: frame k of one view and frame k of the other are a pair
// (the calibration takes the shared views' relative pose from them). A
// frame is paired with the other view's frame nearest in time, within
// half a frame period; a camera that dropped a frame leaves its partner
// unpaired, and it is left out (counted in a warning) rather than paired
// with the wrong instant.
Result<Frames> read_recording(const std::string& dir) {
  auto reader = RecordingReader::open(dir);
  if (!reader) return reader.error();
  for (const auto& w : reader->warnings()) spdlog::warn("{}", w);
  Frames out;
  out.size = cv::Size(static_cast<int>(reader->info().format.width), static_cast<int>(reader->info().format.height));
  const auto tolerance_ns = static_cast<std::int64_t>(0.5e9 / std::max(1.0, reader->info().fps));
  std::size_t next[2] = {0, 0};
  std::size_t unpaired = 0;
  const std::size_t count[2] = {reader->frame_count(View::Frontal), reader->frame_count(View::Lateral)};
  while (next[0] < count[0] && next[1] < count[1]) {
    auto frontal = reader->read(View::Frontal, next[0]);
    if (!frontal) return frontal.error();
    auto lateral = reader->read(View::Lateral, next[1]);
    if (!lateral) return lateral.error();
    const std::int64_t dt = frontal->timestamp_ns() - lateral->timestamp_ns();
    if (std::abs(dt) <= tolerance_ns) {
      out.grey[0].push_back(grey_image(*frontal));
      out.grey[1].push_back(grey_image(*lateral));
      ++next[0];
      ++next[1];
    } else {
      ++next[dt < 0 ? 0 : 1];  // the earlier frame has no partner
      ++unpaired;
    }
  }
  unpaired += (count[0] - next[0]) + (count[1] - next[1]);
  if (unpaired > 0)
    spdlog::warn("{}: {} frames have no partner within half a frame period in the other view; left out", dir, unpaired);
  return out;
}

Result<cv::Size> parse_squares(const std::string& text) {
  int x = 0, y = 0;
  char sep = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &x, &sep, &y, &extra) != 3 || (sep != 'x' && sep != 'X'))
    return Error{fmt::format("--squares: '{}' is not COLUMNSxROWS (e.g. 5x7)", text)};
  return cv::Size(x, y);
}

// Both cameras as `record` opens them: [cameras] of the config (built-in
// defaults without one), the devices the command line names.
Result<std::array<std::unique_ptr<V4l2Camera>, 2>> open_cameras(const std::string& config_path,
                                                                  const std::string devices[2]) {
  Config config;
  if (!config_path.empty()) {
    auto loaded = load_config(config_path);
    if (!loaded) return loaded.error();
    config = std::move(loaded.value());
  }
  const CameraPairOptions pair = camera_pair_options(config);
  V4l2CameraOptions options[2] = {pair.frontal, pair.lateral};
  std::array<std::unique_ptr<V4l2Camera>, 2> cameras;
  for (int v = 0; v < 2; ++v) {
    if (!devices[v].empty()) options[v].path = devices[v];
    cameras[static_cast<std::size_t>(v)] = std::make_unique<V4l2Camera>(options[v]);
    if (auto started = cameras[static_cast<std::size_t>(v)]->start(); !started) return started.error();
  }
  return cameras;
}

// --mirror frontal,lateral: which cameras film mirror-imaged, by index.
std::array<bool, 2> mirrored_cameras(const std::vector<std::string>& names) {
  std::array<bool, 2> mirrored{};
  for (const auto& name : names) mirrored[name == kCameraNames[0] ? 0 : 1] = true;
  return mirrored;
}

// A mirrored camera's frames as the station will get them once its
// mirroring is undone: flipped left to right.
void flip_left_right(std::vector<cv::Mat>& frames) {
  for (cv::Mat& frame : frames) {
    cv::Mat flipped;
    cv::flip(frame, flipped, 1);
    frame = flipped;
  }
}

// Where a refused calibration puts a camera's intrinsics that held:
// calibration.yaml → calibration.frontal-intrinsics.yaml beside it.
std::filesystem::path intrinsics_path(const std::string& out, const char* camera) {
  std::filesystem::path path(out);
  return path.parent_path() / fmt::format("{}.{}-intrinsics.yaml", path.stem().string(), camera);
}

}  // namespace

void add_calibrate_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string views, placement, out = "calibration.yaml";
    std::string videos[2];
    std::string aspect = "square";
    bool legacy = false;
    std::string board = "charuco", squares = "5x7", dictionary = "DICT_4X4_50";
    double square_mm = 150, marker_mm = 115;
    std::string place = "upright";
    double centre_height_mm = 0;
    std::string intrinsics[2];
    std::vector<std::string> mirror;
    CalibrationLimits limits;
    std::string write_board;
    double dpi = 100;
    bool live = false;
    std::string devices[2], config;
    LiveSessionOptions session;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("calibrate", "Calibrate the station's two cameras from recordings of a board");
  cmd->add_option("--views", opts->views,
                  "Recording of the board held at many poses in front of each camera (intrinsics)");
  cmd->add_option("--placement", opts->placement,
                  "Recording of the board placed where the subject will stand (the world frame)");
  cmd->add_option("--frontal-video", opts->videos[0],
                  "The views as a video file of the frontal camera (instead of --views; taken together with "
                  "--lateral-video, frame for frame)");
  cmd->add_option("--lateral-video", opts->videos[1], "The views as a video file of the lateral camera");
  cmd->add_option("--out", opts->out, "calibration.yaml to write")->capture_default_str();
  cmd->add_option("--board", opts->board, "Board kind")
      ->check(CLI::IsMember({"charuco", "chessboard"}))
      ->capture_default_str();
  cmd->add_option("--squares", opts->squares, "Squares across x down the printed board")->capture_default_str();
  cmd->add_option("--square-mm", opts->square_mm, "Side of a square as printed (mm)")
      ->check(CLI::Range(1.0, 1000.0))
      ->capture_default_str();
  cmd->add_option("--marker-mm", opts->marker_mm, "Side of an ArUco marker as printed (mm; ChArUco)")
      ->check(CLI::Range(1.0, 1000.0))
      ->capture_default_str();
  cmd->add_option("--dictionary", opts->dictionary,
                  "ArUco dictionary of the markers (ChArUco): DICT_{4,5,6,7}X{4,5,6,7}_{50,100,250,1000}, "
                  "DICT_ARUCO_ORIGINAL, DICT_APRILTAG_16h5, _25h9, _36h10, _36h11")
      ->capture_default_str();
  cmd->add_flag("--legacy", opts->legacy,
               "ChArUco: the layout of OpenCV before 4.6 (with an even number of rows, a marker in the top left "
               "square)");
  cmd->add_option("--aspect", opts->aspect,
                  "square: refuse fy/fx more than 5 % from 1 (webcams); free: any (anamorphic lenses)")
      ->check(CLI::IsMember({"square", "free"}))
      ->capture_default_str();
  cmd->add_option("--baseline-mm", opts->limits.baseline_mm,
                  "The distance between the two cameras' lenses measured with a tape (mm): refuse a calibration "
                  "more than 5 % off it (a wrong --square-mm)")
      ->check(CLI::Range(1.0, 100000.0));
  cmd->add_option("--place", opts->place, "How the placement board stands: upright (plumb, turned halfway between "
                                          "the cameras) or floor (flat on the floor)")
      ->check(CLI::IsMember({"upright", "floor"}))
      ->capture_default_str();
  cmd->add_option("--board-centre-height", opts->centre_height_mm,
                  "Upright: height of the centre of the board's squares above the floor (mm)")
      ->check(CLI::Range(1.0, 3000.0));
  cmd->add_option("--frontal-intrinsics", opts->intrinsics[0],
                  "The frontal camera's intrinsics from elsewhere (an OpenCV calibration file); no views needed for it");
  cmd->add_option("--lateral-intrinsics", opts->intrinsics[1], "The lateral camera's intrinsics from elsewhere");
  cmd->add_option("--mirror", opts->mirror,
                  "frontal, lateral or frontal,lateral: the cameras whose images are mirrored (left-right flipped, a "
                  "webcam's mirror setting); their frames are flipped before the board is looked for")
      ->delimiter(',')
      ->check(CLI::IsMember({"frontal", "lateral"}));
  cmd->add_option("--max-error", opts->limits.max_error_px, "Refuse above this RMS reprojection error (px)")
      ->check(CLI::Range(0.001, 20.0))
      ->capture_default_str();
  cmd->add_option("--min-views", opts->limits.min_views, "Distinct board poses needed per camera")
      ->check(CLI::Range(3, 1000))
      ->capture_default_str();
  cmd->add_option("--axis-tolerance", opts->limits.axis_tolerance_deg,
                  "Refuse when the optical axes are further than this from 90° apart (degrees)")
      ->check(CLI::Range(0.0, 90.0))
      ->capture_default_str();
  cmd->add_flag("--live", opts->live,
               "Take the views and the placement from both cameras as they stream, instead of --views and "
               "--placement recordings");
  cmd->add_option("--frontal", opts->devices[0], "--live: frontal camera device (default: cameras.frontal)");
  cmd->add_option("--lateral", opts->devices[1], "--live: lateral camera device (default: cameras.lateral)");
  cmd->add_option("--config", opts->config, "--live: TOML configuration for the cameras (default: built-in defaults)");
  cmd->add_option("--live-views", opts->session.views, "--live: views to keep per camera")
      ->check(CLI::Range(3, 200))
      ->capture_default_str();
  cmd->add_option("--placement-frames", opts->session.placement_frames,
                  "--live: still frames of the placement board per camera")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_option("--write-board", opts->write_board, "Write the board as a PNG to print, and exit");
  cmd->add_option("--dpi", opts->dpi, "Resolution of --write-board")->check(CLI::Range(20.0, 1200.0))->capture_default_str();

  auto from = add_calibrate_from_options(cmd);  // --from: another tool's file (calibrate_from.hpp)
  cmd->callback([opts, from, &exit_code] {
    if (run_calibrate_from(*from, opts->out, exit_code)) return;
    // Calibrates, prints the report, writes the file when accepted.
    auto finish = [&](const CalibrationBoard& board, const std::array<CameraFrames, 2>& frames, cv::Size size,
                      const PlacementSpec& placement) {
      const StationCalibration result = calibrate_station(board, frames, size, placement, opts->limits);
      fmt::print("{}", format_report(result.report));
      std::fflush(stdout);
      if (!result.accepted()) {
        // A camera that held is not lost with the other: its intrinsics go
        // to a file of their own, for the next run.
        std::string kept;
        for (int i = 0; i < 2; ++i) {
          const CameraReport& camera = result.report.cameras[static_cast<std::size_t>(i)];
          if (camera.intrinsics_given || !camera.intrinsics_accepted || !camera.intrinsics) continue;
          const auto path = intrinsics_path(opts->out, kCameraNames[i]);
          if (auto s = save_intrinsics(path, *camera.intrinsics); !s) return exit_code.fail(s.error());
          kept += fmt::format("; the {} camera's intrinsics held: wrote {}; reuse them with --{}-intrinsics {}",
                              kCameraNames[i], path.string(), kCameraNames[i],
                              path.string());
        }
        return exit_code.fail(Error{fmt::format("calibrate: refused, {} written ({} problem{}; see above){}",
                                                kept.empty() ? "nothing" : "no calibration",
                                                result.report.problems.size(),
                                                result.report.problems.size() == 1 ? "" : "s", kept)});
      }
      if (auto s = save_calibration(opts->out, result.rig); !s) return exit_code.fail(s.error());
      fmt::print("wrote {}\ncheck it with:  spinewatch check --calibration {}\n", opts->out, opts->out);
      for (std::size_t i = 0; i < 2; ++i)
        if (frames[i].flipped)
          fmt::print("the {} camera's calibration is of its images flipped left to right: the station must get "
                     "them so. Switch the camera's mirroring off (v4l2-ctl -d DEVICE --set-ctrl horizontal_flip=1 "
                     "on a camera that mirrors; docs/calibration.md, \"A mirrored camera\")\n",
                     kCameraNames[i]);
    };
    auto usage = [&exit_code](const std::string& message) {
      spdlog::error("calibrate: {}", message);
      exit_code.value = 2;
    };
    auto squares = parse_squares(opts->squares);
    if (!squares) return usage(squares.error().message);
    BoardSpec spec{.kind = opts->board == "chessboard" ? BoardKind::Chessboard : BoardKind::Charuco,
                   .squares_x = squares->width,
                   .squares_y = squares->height,
                   .square_mm = opts->square_mm,
                   .marker_mm = opts->marker_mm,
                   .dictionary = opts->dictionary,
                   .legacy = opts->legacy};
    auto board = CalibrationBoard::create(spec);
    if (!board) return usage(board.error().message);

    if (!opts->write_board.empty()) {
      const double px_per_mm = opts->dpi / 25.4;
      const double margin_mm = 0.5 * spec.square_mm;
      const cv::Mat image = board->draw(px_per_mm, margin_mm);
      try {
        const auto written = media::write_image(opts->write_board, image);
        if (!written) return exit_code.fail(written.error());
        if (!*written) return exit_code.fail(Error{fmt::format("{}: cannot be written", opts->write_board)});
      } catch (const cv::Exception& e) {
        return exit_code.fail(Error{fmt::format("{}: {}", opts->write_board, e.err)});
      }
      fmt::print("{}: {}; {}x{} px at {} dpi = {:.0f} x {:.0f} mm with the white margin. Print at 100 % (no "
                 "scaling), measure a square and give that size as --square-mm.\n",
                 opts->write_board, board->describe(), image.cols, image.rows, opts->dpi,
                 image.cols / px_per_mm, image.rows / px_per_mm);
      return;
    }

    if (opts->live && (!opts->views.empty() || !opts->placement.empty()))
      return usage("--live takes the views and the placement from the cameras: give neither --views nor --placement");
    if (opts->live && opts->session.views < opts->limits.min_views)
      return usage(fmt::format("--live-views {} is fewer than --min-views {}", opts->session.views,
                               opts->limits.min_views));
    const std::array<bool, 2> mirrored = mirrored_cameras(opts->mirror);
    if (opts->live && !opts->mirror.empty())
      return usage("--mirror flips recorded frames; a live camera that films mirror-imaged flips its own: switch its "
                   "mirroring off (v4l2-ctl -d DEVICE --set-ctrl horizontal_flip=1, V4L2_CID_HFLIP, on a camera "
                   "whose images are mirrored) and calibrate --live without --mirror");
    opts->limits.rules.free_aspect = opts->aspect == "free";
    const bool videos = !opts->videos[0].empty() || !opts->videos[1].empty();
    if (videos && (opts->videos[0].empty() || opts->videos[1].empty()))
      return usage("give both --frontal-video and --lateral-video (the views of the two cameras, taken together)");
    if (videos && (!opts->views.empty() || opts->live))
      return usage("the views come from --views, --frontal-video/--lateral-video or --live: give one of them");
    const bool need_views = opts->intrinsics[0].empty() || opts->intrinsics[1].empty();
    if (!opts->live && !videos && need_views && opts->views.empty())
      return usage("give --views DIR (the board held at poses) or --frontal-video and --lateral-video, or both "
                   "--frontal-intrinsics and --lateral-intrinsics");
    if (!opts->live && !videos && opts->views.empty() && opts->placement.empty())
      return usage("give --placement DIR (the board where the subject will stand), or the views to find it in");
    const PlacementSpec placement{opts->place == "floor" ? Placement::Floor : Placement::Upright,
                                  opts->centre_height_mm};
    if (placement.kind == Placement::Upright && opts->centre_height_mm <= 0)
      return usage("--place upright needs --board-centre-height MM (the centre of the board's squares above the floor)");

    std::array<CameraFrames, 2> frames;
    for (int i = 0; i < 2; ++i)
      if (!opts->intrinsics[i].empty()) {
        auto given = load_intrinsics(opts->intrinsics[i]);
        if (!given) return exit_code.fail(given.error());
        frames[static_cast<std::size_t>(i)].intrinsics = *given;
      }
    cv::Size size;
    if (opts->live) {
      auto cameras = open_cameras(opts->config, opts->devices);
      if (!cameras) return exit_code.fail(cameras.error());
      LiveSessionOptions session = opts->session;
      session.collector.min_corners = opts->limits.min_corners;
      for (int i = 0; i < 2; ++i) session.need_views[static_cast<std::size_t>(i)] = opts->intrinsics[i].empty();
      LiveSessionHooks hooks;
      hooks.progress = [](const std::string& line) {
        fmt::print("{}\n", line);
        std::fflush(stdout);
      };
      hooks.before_placement = [] {
        fmt::print("views done. Now place the board where the subject will stand, in view of both cameras, and "
                   "leave it still{}\n",
                   isatty(STDIN_FILENO) ? "; press Enter when it is in place" : "");
        std::fflush(stdout);
        if (isatty(STDIN_FILENO)) {
          std::string line;
          std::getline(std::cin, line);
        }
      };
      auto live = collect_live({(*cameras)[0].get(), (*cameras)[1].get()}, *board, session, hooks);
      for (auto& c : *cameras) c->stop();
      if (!live) return exit_code.fail(live.error());
      size = live->size;
      for (std::size_t i = 0; i < 2; ++i) {
        frames[i].views = std::move(live->frames[i].views);
        frames[i].placement = std::move(live->frames[i].placement);
      }
      return finish(*board, frames, size, placement);
    }
    if (videos) {
      for (std::size_t i = 0; i < 2; ++i) {
        auto video = read_video(opts->videos[i]);
        if (!video) return exit_code.fail(video.error());
        if (i == 1 && video->size != size)
          return exit_code.fail(Error{fmt::format("{}: {}x{} frames, but {} has {}x{}: both cameras' views must be "
                                                  "at the resolution they will run at",
                                                  opts->videos[1], video->size.width, video->size.height,
                                                  opts->videos[0], size.width, size.height)});
        size = video->size;
        frames[i].views = std::move(video->grey);
      }
    }
    if (!opts->placement.empty()) {
      auto placed = read_recording(opts->placement);
      if (!placed) return exit_code.fail(placed.error());
      if (videos && placed->size != size)
        return exit_code.fail(Error{fmt::format("{}: {}x{} frames, but the videos are {}x{}: record both at the "
                                                "station's resolution",
                                                opts->placement, placed->size.width, placed->size.height, size.width,
                                                size.height)});
      size = placed->size;
      for (int i = 0; i < 2; ++i) frames[static_cast<std::size_t>(i)].placement = std::move(placed->grey[static_cast<std::size_t>(i)]);
    }
    if (!opts->views.empty()) {
      auto views = read_recording(opts->views);
      if (!views) return exit_code.fail(views.error());
      if (!opts->placement.empty() && views->size != size)
        return exit_code.fail(Error{fmt::format("{}: {}x{} frames, but {} has {}x{}: record both at the station's "
                                                "resolution",
                                                opts->views, views->size.width, views->size.height, opts->placement,
                                                size.width, size.height)});
      size = views->size;
      for (int i = 0; i < 2; ++i) frames[static_cast<std::size_t>(i)].views = std::move(views->grey[static_cast<std::size_t>(i)]);
    }

    for (std::size_t i = 0; i < 2; ++i)
      if (mirrored[i]) {
        flip_left_right(frames[i].views);
        flip_left_right(frames[i].placement);
        frames[i].flipped = true;
      }
    finish(*board, frames, size, placement);
  });
}

}  // namespace spinewatch::cli
