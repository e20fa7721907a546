// spinewatch import: two video files and another tool's calibration into
// a recording directory (interfaces.md §4; docs/import.md).
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/import/importer.hpp"

namespace spinewatch::cli {
namespace {

struct ImportCli {
  import::ImportOptions options;
  std::string cameras, crop;
  std::optional<int> frames;
};

// "F,L": the frontal and the lateral camera's ids or names.
Status split_cameras(const std::string& text, import::ImportOptions& o) {
  const std::size_t comma = text.find(',');
  if (comma == std::string::npos || comma == 0 || comma + 1 == text.size() ||
      text.find(',', comma + 1) != std::string::npos)
    return Error{fmt::format("--cameras \"{}\": expected FRONTAL,LATERAL (two ids or names of the calibration)", text)};
  o.frontal_camera = text.substr(0, comma);
  o.lateral_camera = text.substr(comma + 1);
  return Ok{};
}

void run(ImportCli& cli, ExitCode& exit_code) {
  import::ImportOptions& o = cli.options;
  if (!cli.cameras.empty())
    if (auto s = split_cameras(cli.cameras, o); !s) return exit_code.fail(s.error(), 2);
  if (!cli.crop.empty()) {
    if (o.crop_frontal.empty()) o.crop_frontal = cli.crop;
    if (o.crop_lateral.empty()) o.crop_lateral = cli.crop;
  }
  o.frames = cli.frames;
  auto summary = import::import_recording(o);
  if (!summary) return exit_code.fail(summary.error());
  spdlog::info("{}: {} frame pairs, 320x240 YUYV, in {:.2f} s", o.out.string(), summary->pairs, summary->seconds);
}

}  // namespace

void add_import_command(CLI::App& app, ExitCode& exit_code) {
  auto cli = std::make_shared<ImportCli>();
  import::ImportOptions& o = cli->options;
  auto* cmd = app.add_subcommand("import", "Two videos and another tool's calibration into a recording directory");
  cmd->add_option("--frontal", o.frontal_video, "the frontal camera's video (mp4/H.264, avi, mkv, …)")->required();
  cmd->add_option("--lateral", o.lateral_video, "the lateral camera's video")->required();
  cmd->add_option("--calibration", o.calibration,
                  "caliscope camera_array.toml, anipose calibration.toml, or OpenCV YAML/JSON (frontal, lateral)")
      ->required();
  cmd->add_option("--out", o.out, "the recording directory to write")->required();
  cmd->add_option("--cameras", cli->cameras, "F,L: the two cameras of a multi-camera file, by id or name "
                                              "(default: its first two)");
  cmd->add_option("--background-frontal", o.background_frontal, "the frontal camera's empty scene (full frame)");
  cmd->add_option("--background-lateral", o.background_lateral, "the lateral camera's empty scene (full frame)");
  cmd->add_flag("--median-background", o.median_background,
                "store the per-pixel median of each imported clip as its background");
  cmd->add_option("--offset", o.offset, "lateral frame i+N pairs with frontal frame i")->capture_default_str();
  cmd->add_option("--frames", cli->frames, "import only the first N pairs")->check(CLI::PositiveNumber);
  cmd->add_option("--crop", cli->crop, "X,Y,W,H (4:3) for both cameras (default: around where each clip moves)");
  cmd->add_option("--crop-frontal", o.crop_frontal, "X,Y,W,H (4:3) of the frontal video");
  cmd->add_option("--crop-lateral", o.crop_lateral, "X,Y,W,H (4:3) of the lateral video");
  cmd->add_option("--up", o.up, "X,Y,Z: the up direction in the calibration's frame (default: the cameras' mean "
                                "image up)");
  cmd->add_option("--camera-height", o.camera_height_mm, "the cameras' mean height above the floor, mm")
      ->check(CLI::Range(0.0, 10000.0))
      ->capture_default_str();
  cmd->footer("Frames are cropped (4:3) and scaled to 320x240, colour kept (YUYV); calibration.yaml matches the "
              "crop and scale exactly and is put in the station's world frame (docs/import.md).\n");
  cmd->callback([cli, &exit_code] { run(*cli, exit_code); });
}

}  // namespace spinewatch::cli
