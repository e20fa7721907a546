// spinewatch phantom: render a synthetic subject into a recording directory
// with ground truth (docs/phantom.md).
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string_view>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>  // the flags; the codecs are the media module's
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/media/media_files.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch {
// config/subjects/ansur-15936.json, embedded (tools/CMakeLists.txt).
std::string_view default_subject_json();
}  // namespace spinewatch

namespace spinewatch::cli {
namespace {

// A photograph to use as a view's room: any image OpenCV reads; one
// message naming the file when it cannot be read.
Result<cv::Mat> load_backdrop(const std::filesystem::path& path) {
  auto read = media::read_image(path, cv::IMREAD_COLOR);
  if (!read) return read.error();
  cv::Mat image = std::move(*read);
  if (image.empty())
    return Error{fmt::format("{}: cannot read it as an image (give a PNG or JPEG photograph of the room)", path.string())};
  return image;
}

// The default subject is a measured adult: ANSUR II subject 15936, the test
// set's median man, his spine placed from his own C7 and iliac-crest
// landmarks (docs/anthropometry.md). It is embedded, so that the phantom,
// and the demo recording rendered with it at build time, need no data
// beside the repository. "generic" names the generic anatomy the model was
// first built on, whose spine sits lower in the body than measured people's.
Result<phantom::Subject> named_subject(const std::string& spec) {
  if (spec.empty())
    return phantom::parse_subject(nlohmann::json::parse(default_subject_json()), "the default subject");
  if (spec == "generic") return phantom::Subject{};
  if (spec.starts_with(phantom::kAnsurSubjectPrefix)) {
    const auto dir = phantom::default_ansur_dir();
    auto subject = phantom::load_ansur_subject(spec, dir);
    std::error_code ec;
    if (!subject && !std::filesystem::is_directory(dir, ec))
      return Error{fmt::format("{}: the ANSUR II data is not at {} (relative to {}): set $SPINEWATCH_ANSUR_DIR to the "
                               "directory holding ANSUR_II_MALE_Public.csv and ANSUR_II_FEMALE_Public.csv, or run "
                               "from the repository's root with ../shared beside it",
                               spec, dir.string(), std::filesystem::current_path(ec).string())};
    return subject;
  }
  return phantom::load_subject(spec);
}

}  // namespace

void add_phantom_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    phantom::PhantomOptions phantom;
    std::string scenario, out, subject, calibration;
    int frames = 0;
    bool list = false;
    // Station geometry and scene (docs/phantom.md).
    std::optional<double> tilt, roll, pair_angle, height;
    std::string room, backdrop_frontal, backdrop_lateral, chair;
    bool desk = false, no_desk = false;
  };
  auto opts = std::make_shared<Options>();
  std::vector<std::string> names;
  for (const auto& s : phantom::scenarios()) names.emplace_back(s.name);

  auto* cmd = app.add_subcommand("phantom", "Render a synthetic subject into a recording directory with ground truth");
  cmd->add_flag("--list", opts->list, "List the scenarios and exit");
  cmd->add_option("--scenario", opts->scenario, "Scenario to play (see --list)")->check(CLI::IsMember(names));
  cmd->add_option("--out", opts->out, "Recording directory to write");
  cmd->add_option("--subject", opts->subject,
                  "Subject JSON, ansur:ID for that measured adult of ANSUR II (in $SPINEWATCH_ANSUR_DIR, else "
                  "../shared/data/ansur2), or generic for the generic anatomy (default: a measured adult, ANSUR II "
                  "15936, config/subjects/ansur-15936.json)");
  cmd->add_option("--frames", opts->frames, "Person frames after the empty ones (default: the scenario's)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--seed", opts->phantom.seed, "Seed of everything random (texture, noise, the subject's joint factors)")
      ->capture_default_str();
  cmd->add_option("--noise", opts->phantom.noise_sigma, "Sensor noise, standard deviation in grey levels")
      ->check(CLI::Range(0.0, 50.0))
      ->capture_default_str();
  cmd->add_option("--flicker", opts->phantom.flicker, "Exposure flicker, relative gain amplitude per frame")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  cmd->add_flag("--shadow", opts->phantom.shadow, "Cast a soft shadow onto the wall and floor");
  cmd->add_option("--light-drift", opts->phantom.light_drift,
                  "The light falls by this fraction over the recording, unevenly across each view")
      ->check(CLI::Range(0.0, 0.6))
      ->capture_default_str();
  cmd->add_flag("--passer-by", opts->phantom.passer_by, "A second person walks behind the subject");
  cmd->add_flag("--colour", opts->phantom.colour,
                "Cameras in colour: YUYV with chroma (a warm wall, a blue shirt); else grey chroma");
  cmd->add_flag("--camouflage", opts->phantom.camouflage,
                "Clothing and skin as bright as the wall behind them (with --colour, only colour tells them apart)");
  cmd->add_option("--empty-frames", opts->phantom.empty_frames, "Empty-scene frames before the person appears")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str();
  cmd->add_option("--calibration", opts->calibration, "calibration.yaml of the rig (default: the documented default rig)");
  auto* geometry = cmd->add_option_group("station geometry", "The rig built from these (not with --calibration)");
  geometry->add_option("--camera-tilt", opts->tilt, "Both cameras look down by DEG at the trunk")->check(CLI::Range(0.0, 45.0));
  geometry->add_option("--camera-roll", opts->roll, "Both cameras rolled by DEG about their axes")->check(CLI::Range(0.0, 25.0));
  geometry->add_option("--pair-angle", opts->pair_angle, "Angle between the two views, DEG (default rig: 90)")
      ->check(CLI::Range(45.0, 135.0));
  geometry->add_option("--camera-height", opts->height, "The cameras' height above the floor, MM (default rig: 1100)")
      ->check(CLI::Range(300.0, 3500.0));
  cmd->add_option("--heading", opts->phantom.heading_deg,
                  "Which way the subject faces, DEG counter-clockwise from above (180: back to the frontal camera)")
      ->check(CLI::Range(-360.0, 360.0));
  cmd->add_option("--room", opts->room, "The room: plain (default) or cluttered")
      ->check(CLI::IsMember({"plain", "cluttered"}));
  cmd->add_option("--backdrop-frontal", opts->backdrop_frontal, "A photograph used as the frontal view's room")
      ->check(CLI::ExistingFile);
  cmd->add_option("--backdrop-lateral", opts->backdrop_lateral, "A photograph used as the lateral view's room")
      ->check(CLI::ExistingFile);
  auto* desk = cmd->add_flag("--desk", opts->desk,
                             "A desk (seated) or bench (standing) in front of the subject; on by default in typing and reach");
  cmd->add_flag("--no-desk", opts->no_desk, "No desk or bench, whatever the scenario")->excludes(desk);
  cmd->add_option("--chair", opts->chair,
                  "A chair under the seated subject (seat, legs, backrest), part of the room: black (an office "
                  "chair, darker than dark trousers by less than the silhouette threshold) or grey; seated scenarios only")
      ->check(CLI::IsMember({"black", "grey"}));
  cmd->add_option("--h264", opts->phantom.h264_crf,
                  "Compress the written frames with H.264 at this CRF (0 lossless, 23 x264's default, 51 worst)")
      ->check(CLI::Range(0, 51));

  cmd->callback([opts, &exit_code] {
    if (opts->list) {
      for (const auto& s : phantom::scenarios())
        fmt::print("{:<15} {:>4} frames  {}\n", s.name, s.default_frames, s.description);
      return;
    }
    if (opts->scenario.empty() || opts->out.empty()) {
      spdlog::error("phantom: give --scenario NAME and --out DIR (or --list)");
      exit_code.value = 2;
      return;
    }
    phantom::PhantomOptions& p = opts->phantom;
    p.scenario = opts->scenario;
    if (opts->frames > 0) p.frames = opts->frames;
    auto subject = named_subject(opts->subject);
    if (!subject) return exit_code.fail(subject.error());
    p.subject = std::move(subject).value();
    const bool station = opts->tilt || opts->roll || opts->pair_angle || opts->height;
    if (station && !opts->calibration.empty()) {
      spdlog::error("phantom: --calibration gives the rig; --camera-tilt, --camera-roll, --pair-angle and "
                    "--camera-height build one: give one or the other");
      exit_code.value = 2;
      return;
    }
    if (station)
      p.station = phantom::StationGeometry{opts->tilt, opts->roll.value_or(0), opts->pair_angle.value_or(90), opts->height};
    if (opts->desk || opts->no_desk) p.desk = opts->desk;
    if (opts->room == "cluttered") p.room = phantom::RoomKind::Cluttered;
    if (!opts->chair.empty()) p.chair = opts->chair == "black" ? phantom::Chair::Black : phantom::Chair::Grey;
    if (opts->backdrop_frontal.empty() != opts->backdrop_lateral.empty()) {
      spdlog::error("phantom: give --backdrop-frontal and --backdrop-lateral together");
      exit_code.value = 2;
      return;
    }
    if (!opts->backdrop_frontal.empty()) {
      if (!opts->room.empty()) {
        spdlog::error("phantom: --room and the backdrop photographs both say what the room is: give one of them");
        exit_code.value = 2;
        return;
      }
      for (View view : kViews) {
        const std::string& path = view == View::Frontal ? opts->backdrop_frontal : opts->backdrop_lateral;
        auto image = load_backdrop(path);
        if (!image) return exit_code.fail(image.error());
        p.backdrop[static_cast<std::size_t>(view)] = std::move(image).value();
      }
    }
    if (!opts->calibration.empty()) {
      auto rig = load_calibration(opts->calibration);
      if (!rig) return exit_code.fail(rig.error());
      if (auto s = check_image_size(*rig, phantom::kImageWidth, phantom::kImageHeight); !s)
        return exit_code.fail(Error{opts->calibration + ": " + s.error().message});
      p.rig = std::move(rig).value();
    }
    auto sequence = phantom::PhantomSequence::create(p);
    if (!sequence) {
      spdlog::error("phantom: {}", sequence.error().message);
      exit_code.value = 2;  // the options above are range-checked; what is left is a bad value
      return;
    }
    const auto start = std::chrono::steady_clock::now();
    if (auto s = phantom::write_recording(*sequence, opts->out); !s) return exit_code.fail(s.error());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    spdlog::info("phantom: {} frames of '{}' ({} empty) written to {} in {:.2f} s", sequence->frame_count(),
                 sequence->scenario().name, p.empty_frames, opts->out, seconds);
    // A subject without measured landmarks (the named ones) keeps the
    // anatomy the generic model was built on: replayed with the default
    // (measured) spine placement its spine scores about 65 mm off, which
    // says nothing about the fit.
    if (!p.subject.t1_height_mm && !p.subject.l5_height_mm)
      spdlog::info("phantom: subject '{}' has the phantom's generic anatomy, not a measured person's; to score the fit "
                   "on it, replay with [subject] spine_placement = \"generic\" (docs/anthropometry.md); "
                   "the default subject and --subject ansur:ID are measured adults",
                   p.subject.name);
  });
}

}  // namespace spinewatch::cli
