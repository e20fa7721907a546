// spinewatch phantom: render a synthetic subject into a recording directory
// with ground truth (docs/phantom.md).
#include <chrono>
#include <filesystem>
#include <memory>
#include <string_view>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch {
// config/subjects/ansur-15936.json, embedded (tools/CMakeLists.txt).
std::string_view default_subject_json();
}  // namespace spinewatch

namespace spinewatch::cli {
namespace {

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
