#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <set>
#include <tuple>

#include <fmt/format.h>

#include "ops/config_reload.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/estimator_options.hpp"
#include "support/nearest_name.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

TEST(Config, EmptyFileGivesDefaults) {
  auto c = parse_config("", "empty.toml");
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c->publish.listen, "127.0.0.1:7117");
  EXPECT_EQ(c->cameras.width, 320);
  EXPECT_DOUBLE_EQ(c->cameras.fps, 30.0);
}

TEST(Config, ReadsValues) {
  auto c = parse_config("[cameras]\nfps = 60\nwidth = 640\n[station]\nname = \"desk-3\"\n", "x.toml");
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_DOUBLE_EQ(c->cameras.fps, 60.0);  // an integer is accepted where a number is expected
  EXPECT_EQ(c->cameras.width, 640);
  EXPECT_EQ(c->station.name, "desk-3");
}

TEST(Config, UnknownKeyNamesKeyAndLine) {
  auto c = parse_config("[cameras]\nfps = 30\nfpz = 30\n", "station.toml");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().message, "station.toml:3: cameras.fpz: unknown key; did you mean cameras.fps?");
}

TEST(Config, UnknownSection) {
  auto c = parse_config("\n[camera]\nfps = 30\n", "station.toml");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().message, "station.toml:2: [camera]: unknown section; did you mean [cameras]?");
}

// A typo names the key meant; a name near none of them, or equally near two, names none.
TEST(Config, UnknownKeySuggestsTheNearestKnownOne) {
  auto error = [](const std::string& text) { return parse_config(text, "s.toml").error().message; };
  EXPECT_EQ(error("[publish]\nunix_sockt = \"none\"\n"),
            "s.toml:2: publish.unix_sockt: unknown key; did you mean publish.unix_socket?");
  EXPECT_EQ(error("[subject]\nc7_hieght_mm = 1500\n"),
            "s.toml:2: subject.c7_hieght_mm: unknown key; did you mean subject.c7_height_mm?");
  EXPECT_EQ(error("[publsh]\nlisten = \"none\"\n"), "s.toml:1: [publsh]: unknown section; did you mean [publish]?");
  EXPECT_EQ(error("[cameras]\nframerate = 30\n"), "s.toml:2: cameras.framerate: unknown key");
}

TEST(NearestName, EditDistanceAndTies) {
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("fps", "fps"), 0u);
  EXPECT_EQ(nearest_name("fpz", {"fps", "width"}, 1), "fps");
  EXPECT_EQ(nearest_name("ab", {"aa", "bb"}, 1), std::nullopt);  // equally near: no guess
  EXPECT_EQ(nearest_name("zzzz", {"fps"}, 3), std::nullopt);
}

TEST(Config, TopLevelKeyIsUnknown) {
  auto c = parse_config("fps = 30\n", "station.toml");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().message, "station.toml:1: fps: unknown key");
}

TEST(Config, WrongTypeNamesKeyAndLine) {
  auto c = parse_config("[cameras]\n\nwidth = \"wide\"\n", "station.toml");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().message, "station.toml:3: cameras.width: expected an integer, got string");
  auto d = parse_config("[cameras]\nfps = \"fast\"\n", "s.toml");
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.error().message, "s.toml:2: cameras.fps: expected a number, got string");
  auto e = parse_config("[station]\nname = 3\n", "s.toml");
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().message, "s.toml:2: station.name: expected a string, got integer");
  auto f = parse_config("[cameras]\nwidth = 320.5\n", "s.toml");
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.error().message, "s.toml:2: cameras.width: expected an integer, got floating-point");
}

TEST(Config, OutOfRangeNamesKeyAndLine) {
  auto c = parse_config("[cameras]\nfps = 500\n", "station.toml");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().message, "station.toml:2: cameras.fps: 500 is out of range [1, 120]");
  auto d = parse_config("[cameras]\nbuffers = 2\n", "station.toml");
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.error().message, "station.toml:2: cameras.buffers: 2 is out of range [4, 32]");
}

TEST(Config, EnumValueOutsideTheSet) {
  auto c = parse_config("[trigger]\nmode = \"sometimes\"\n", "station.toml");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().message, "station.toml:2: trigger.mode: \"sometimes\" is not one of: free-run, master, slave");
}

// Every mode is parsed once, at load, into its enum; code switches on the
// enum. Each name gives its value, and any other text is refused naming
// key and line.
TEST(Config, ModesAreParsedOnceIntoEnums) {
  auto parse = [](const std::string& section, const std::string& key, const std::string& value) {
    return parse_config("[" + section + "]\n" + key + " = \"" + value + "\"\n", "s.toml");
  };
  const Config defaults = *parse_config("", "s.toml");
  EXPECT_EQ(defaults.cameras.source, CameraSource::Auto);
  EXPECT_EQ(defaults.cameras.replay, ReplayPace::Paced);
  EXPECT_EQ(defaults.cameras.pixel_format, PixelFormat::YUYV);
  EXPECT_EQ(defaults.trigger.mode, sync::TriggerMode::FreeRun);
  EXPECT_EQ(defaults.silhouette.background, BackgroundMode::Learn);
  EXPECT_EQ(defaults.subject.spine_placement, SpinePlacementMode::Measured);
  for (auto [text, mode] : {std::pair{"auto", CameraSource::Auto}, {"v4l2", CameraSource::V4l2},
                            {"libcamera", CameraSource::Libcamera}, {"recording", CameraSource::Recording}}) {
    EXPECT_EQ(parse("cameras", "source", text)->cameras.source, mode) << text;
    EXPECT_EQ(to_string(mode), text);
  }
  EXPECT_EQ(parse("cameras", "replay", "fast")->cameras.replay, ReplayPace::Fast);
  EXPECT_EQ(to_string(ReplayPace::Fast), "fast");
  EXPECT_EQ(parse("cameras", "pixel_format", "GREY")->cameras.pixel_format, PixelFormat::GREY);
  EXPECT_EQ(parse("trigger", "mode", "master")->trigger.mode, sync::TriggerMode::Master);
  EXPECT_EQ(defaults.log.level, LogLevel::Info);
  for (const auto& [text, level] : log_level_names()) EXPECT_EQ(parse("log", "level", text)->log.level, level) << text;
  EXPECT_EQ(parse("trigger", "mode", "slave")->trigger.mode, sync::TriggerMode::Slave);
  EXPECT_EQ(parse("silhouette", "background", "image")->silhouette.background, BackgroundMode::Image);
  EXPECT_EQ(parse("silhouette", "background", "threshold")->silhouette.background, BackgroundMode::Threshold);
  EXPECT_EQ(parse("subject", "spine_placement", "generic")->subject.spine_placement, SpinePlacementMode::Generic);
  // A mode's name is case-sensitive and exact.
  for (auto [section, key, bad, names] :
       {std::tuple{"cameras", "source", "V4L2", "auto, v4l2, libcamera, recording"},
        {"cameras", "replay", "slow", "paced, fast"},
        {"cameras", "pixel_format", "MJPG", "YUYV, GREY"},
        {"trigger", "mode", "free-run ", "free-run, master, slave"},
        {"silhouette", "background", "Learn", "learn, image, threshold"},
        {"subject", "spine_placement", "ansur", "measured, generic"}}) {
    auto r = parse(section, key, bad);
    ASSERT_FALSE(r.ok()) << key;
    EXPECT_EQ(r.error().message,
              fmt::format("s.toml:2: {}.{}: \"{}\" is not one of: {}", section, key, bad, names));
  }
  auto wrong_type = parse_config("[cameras]\nsource = 4\n", "s.toml");
  ASSERT_FALSE(wrong_type.ok());
  EXPECT_EQ(wrong_type.error().message, "s.toml:2: cameras.source: expected a string, got integer");
}

TEST(Config, SyntaxErrorNamesLine) {
  auto c = parse_config("[cameras]\nfps = = 3\n", "station.toml");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().message.rfind("station.toml:2: ", 0), 0u) << c.error().message;
}

// Found by the config_toml fuzzer (tests/fuzz): toml++ quotes the
// character it stopped at, and a line end there split the message (and
// the log line) in two; quoted keys may hold line ends too.
TEST(Config, AMessageStaysOneLineWhateverTheInputHolds) {
  auto number = parse_config("[cameras]\nfps = n\nn", "station.toml");
  ASSERT_FALSE(number.ok());
  EXPECT_EQ(number.error().message.find('\n'), std::string::npos) << number.error().message;
  EXPECT_EQ(number.error().message.rfind("station.toml:2: ", 0), 0u) << number.error().message;
  EXPECT_NE(number.error().message.find("\\n"), std::string::npos) << number.error().message;

  auto section = parse_config("[\"cam\\neras\"]\nfps = 3\n", "station.toml");
  ASSERT_FALSE(section.ok());
  EXPECT_EQ(section.error().message, "station.toml:1: [cam\\neras]: unknown section; did you mean [cameras]?");
  auto key = parse_config("[cameras]\n\"f\\u0001ps\" = 3\n", "station.toml");
  ASSERT_FALSE(key.ok());
  EXPECT_EQ(key.error().message, "station.toml:2: cameras.f\\x01ps: unknown key");
  // A mode's value is quoted too (found by the config_toml fuzzer:
  // corpus/config_toml/regression-line-end-in-a-mode.toml).
  auto mode = parse_config("[log]\nlevel = \"in\\nfo\"\n", "station.toml");
  ASSERT_FALSE(mode.ok());
  EXPECT_EQ(mode.error().message.find('\n'), std::string::npos) << mode.error().message;
  EXPECT_NE(mode.error().message.find("log.level: \"in\\nfo\" is not one of: "), std::string::npos) << mode.error().message;
}

TEST(Config, MissingFile) {
  auto c = load_config("/nonexistent/spinewatch.toml");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error().message, "/nonexistent/spinewatch.toml: cannot open: No such file or directory");
}

// The annotated default file must list every key the loader knows, with
// the loader's defaults, and nothing else.
TEST(Config, AnnotatedDefaultFileListsEveryKeyWithItsDefault) {
  const auto path = test::source_path("config/spinewatch.toml");
  auto c = load_config(path);
  ASSERT_TRUE(c.ok()) << c.error().message;
  const std::string text = test::read_file(path);
  std::set<std::string> in_file;
  std::string section;
  std::regex section_re(R"(^\[([a-z_]+)\]\s*$)"), key_re(R"(^([a-z_0-9]+)\s*=)");
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, section_re)) section = m[1];
    else if (std::regex_search(line, m, key_re)) in_file.insert(section + "." + std::string(m[1]));
  }
  const auto keys = config_keys();
  EXPECT_EQ(in_file, std::set<std::string>(keys.begin(), keys.end()));

  EXPECT_TRUE(*c == Config{}) << "config/spinewatch.toml and config.hpp disagree on a default";
}

}  // namespace
}  // namespace spinewatch

namespace spinewatch {
namespace {

// subject.spine_placement reaches the estimator (its effect on the
// postures: tests/tools/population, PopulationSweep.MeasuredPlacementOnTestSubjectsBeatsTheGenericSpine).
TEST(Config, SpinePlacementReachesTheEstimatorAndRefusesOtherNames) {
  EXPECT_EQ(estimator_options(*parse_config("", "s.toml")).subject.spine_placement, SpinePlacementMode::Measured);
  auto generic = parse_config("[subject]\nspine_placement = \"generic\"\n", "s.toml");
  ASSERT_TRUE(generic) << generic.error().message;
  EXPECT_EQ(estimator_options(*generic).subject.spine_placement, SpinePlacementMode::Generic);
  auto bad = parse_config("[subject]\nspine_placement = \"ansur\"\n", "s.toml");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "s.toml:2: subject.spine_placement: \"ansur\" is not one of: measured, generic");
}

// cvsm.refine_steps reaches the estimator, one step by default (its effect
// on the postures: tests/estimator/cvsm, CvsmRefinement.BringsTheFitCloserToAnotherSubjectsPose;
// through replay --config: tests/tools/calibrate, CalibrateCli.ReplayWith…).
TEST(Config, RefineStepsReachTheEstimatorOneStepByDefault) {
  EXPECT_EQ(estimator_options(*parse_config("", "s.toml")).cvsm.refine_steps, 1);
  auto off = parse_config("[cvsm]\nrefine_steps = 0\n", "s.toml");
  ASSERT_TRUE(off) << off.error().message;
  EXPECT_EQ(estimator_options(*off).cvsm.refine_steps, 0);
  auto on = parse_config("[cvsm]\nrefine_steps = 2\n", "s.toml");
  ASSERT_TRUE(on) << on.error().message;
  EXPECT_EQ(estimator_options(*on).cvsm.refine_steps, 2);
  auto bad = parse_config("[cvsm]\nrefine_steps = 9\n", "s.toml");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "s.toml:2: cvsm.refine_steps: 9 is out of range [0, 4]");
  // The key's former name is refused with its new one.
  auto renamed = parse_config("[cvsm]\nrefine_sweeps = 1\n", "s.toml");
  ASSERT_FALSE(renamed);
  EXPECT_EQ(renamed.error().message, "s.toml:2: cvsm.refine_sweeps: unknown key; it is now cvsm.refine_steps");
}

// cvsm.limbs reaches the estimator, "auto" by default (its effect on the
// fit: tests/estimator/cvsm, CvsmLimbs.ArticulatedFitKeepsTheTrunkWhereTheFixedOneIsPulledOff,
// CvsmLimbs.Auto*).
TEST(Config, LimbsReachTheEstimatorAutoByDefault) {
  EXPECT_EQ(estimator_options(*parse_config("", "s.toml")).cvsm.limbs, LimbMode::Auto);
  auto fixed = parse_config("[cvsm]\nlimbs = \"fixed\"\n", "s.toml");
  ASSERT_TRUE(fixed) << fixed.error().message;
  EXPECT_EQ(estimator_options(*fixed).cvsm.limbs, LimbMode::Fixed);
  auto on = parse_config("[cvsm]\nlimbs = \"articulated\"\n", "s.toml");
  ASSERT_TRUE(on) << on.error().message;
  EXPECT_EQ(estimator_options(*on).cvsm.limbs, LimbMode::Articulated);
  auto automatic = parse_config("[cvsm]\nlimbs = \"auto\"\n", "s.toml");
  ASSERT_TRUE(automatic) << automatic.error().message;
  EXPECT_EQ(estimator_options(*automatic).cvsm.limbs, LimbMode::Auto);
  auto bad = parse_config("[cvsm]\nlimbs = \"free\"\n", "s.toml");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "s.toml:2: cvsm.limbs: \"free\" is not one of: fixed, articulated, auto");
}

// cvsm.heading reaches the estimator, "front" by default (its effect on the
// fit: tests/estimator/cvsm/heading_test.cpp, CvsmHeading.*).
TEST(Config, HeadingReachesTheEstimatorFrontByDefault) {
  EXPECT_EQ(estimator_options(*parse_config("", "s.toml")).cvsm.heading, HeadingRange::Front);
  for (const auto& [text, range] : {std::pair{"fixed", HeadingRange::Fixed}, std::pair{"any", HeadingRange::Any}}) {
    auto on = parse_config(std::string("[cvsm]\nheading = \"") + text + "\"\n", "s.toml");
    ASSERT_TRUE(on) << on.error().message;
    EXPECT_EQ(estimator_options(*on).cvsm.heading, range) << text;
  }
  auto bad = parse_config("[cvsm]\nheading = \"back\"\n", "s.toml");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "s.toml:2: cvsm.heading: \"back\" is not one of: fixed, front, any");
}

TEST(Config, AKnownWorkersStatureAndMassReachTheEstimatorAndZeroIsNotKnown) {
  const EstimatorOptions unknown = estimator_options(*parse_config("", "s.toml"));
  EXPECT_EQ(known_worker(unknown.subject), KnownWorker{}) << "by default the worker is not known";
  auto known = parse_config("[subject]\nstature_mm = 1712\nmass_kg = 68.5\n", "s.toml");
  ASSERT_TRUE(known) << known.error().message;
  EXPECT_EQ(known_worker(estimator_options(*known).subject), (KnownWorker{1712.0, 68.5}));
  auto zero = parse_config("[subject]\nstature_mm = 0\nmass_kg = 80\n", "s.toml");
  ASSERT_TRUE(zero) << zero.error().message;
  EXPECT_EQ(known_worker(estimator_options(*zero).subject), (KnownWorker{std::nullopt, 80.0}));
  auto bad = parse_config("[subject]\nstature_mm = 500\n", "s.toml");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "s.toml:2: subject.stature_mm: 500 is out of range [1000, 2300] (0 = not known)");
  auto heavy = parse_config("[subject]\n\nmass_kg = 260\n", "s.toml");
  ASSERT_FALSE(heavy);
  EXPECT_EQ(heavy.error().message, "s.toml:3: subject.mass_kg: 260 is out of range [20, 250] (0 = not known)");
  // A new worker is applied on SIGHUP, without a restart.
  EXPECT_TRUE(reloadable_key("subject.stature_mm"));
  EXPECT_TRUE(reloadable_key("subject.mass_kg"));
  EXPECT_EQ(changed_keys(*zero, *known), (std::vector<std::string>{"subject.stature_mm", "subject.mass_kg"}));
}

TEST(Config, AKnownWorkersLandmarksReachTheEstimatorCheckedTogether) {
  auto known = parse_config("[subject]\nstature_mm = 1755\nc7_height_mm = 1500\niliac_crest_height_mm = 1040\n", "s.toml");
  ASSERT_TRUE(known) << known.error().message;
  EXPECT_EQ(known_worker(estimator_options(*known).subject), (KnownWorker{1755.0, std::nullopt, 1500.0, 1040.0}));
  auto range = parse_config("[subject]\niliac_crest_height_mm = 300\n", "s.toml");
  ASSERT_FALSE(range);
  EXPECT_EQ(range.error().message,
            "s.toml:2: subject.iliac_crest_height_mm: 300 is out of range [500, 1400] (0 = not known)");
  // Each within its range, but not together: the error at the key the check names.
  auto crossed = parse_config("[subject]\nc7_height_mm = 1100\n\niliac_crest_height_mm = 1000\n", "s.toml");
  ASSERT_FALSE(crossed);
  EXPECT_EQ(crossed.error().message,
            "s.toml:4: subject.iliac_crest_height_mm: 1000 mm is not at least 250 mm below c7_height_mm (1100 mm)");
  auto above = parse_config("[subject]\nc7_height_mm = 1600\nstature_mm = 1650\n", "s.toml");
  ASSERT_FALSE(above);
  EXPECT_EQ(above.error().message,
            "s.toml:2: subject.c7_height_mm: 1600 mm is not at least 100 mm below the stature (1650 mm)");
  EXPECT_TRUE(reloadable_key("subject.c7_height_mm"));
  EXPECT_TRUE(reloadable_key("subject.iliac_crest_height_mm"));
  auto none = parse_config("[subject]\nstature_mm = 1755\n", "s.toml");
  EXPECT_EQ(changed_keys(*none, *known),
            (std::vector<std::string>{"subject.c7_height_mm", "subject.iliac_crest_height_mm"}));
}

}  // namespace
}  // namespace spinewatch

namespace spinewatch {
namespace {

TEST(Config, HttpKeysAreReadAndChecked) {
  auto c = parse_config("[http]\nlisten = \"127.0.0.1:8080\"\nfps = 2.5\ncamera_pixels = true\nmax_connections = 4\n"
                        "timeout_s = 1.5\nallow_unauthenticated = true\n",
                        "h.toml");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c->http.listen, "127.0.0.1:8080");
  EXPECT_EQ(c->http.fps, 2.5);
  EXPECT_TRUE(c->http.camera_pixels);
  EXPECT_EQ(c->http.max_connections, 4);
  EXPECT_EQ(c->http.timeout_s, 1.5);
  EXPECT_TRUE(c->http.allow_unauthenticated);
  EXPECT_EQ(Config{}.http.listen, "") << "off by default";
  EXPECT_EQ(parse_config("[http]\nfps = 60\n", "h.toml").error().message, "h.toml:2: http.fps: 60 is out of range [0.2, 30]");
  EXPECT_EQ(parse_config("\n[http]\nmax_connections = 0\n", "h.toml").error().message,
            "h.toml:3: http.max_connections: 0 is out of range [1, 256]");
  EXPECT_EQ(parse_config("[http]\ncamera_pixels = \"yes\"\n", "h.toml").error().message,
            "h.toml:2: http.camera_pixels: expected true or false, got string");
  EXPECT_EQ(parse_config("[http]\nport = 8080\n", "h.toml").error().message, "h.toml:2: http.port: unknown key");
}

}  // namespace
}  // namespace spinewatch

namespace spinewatch {
namespace {

// The annotated configuration is checked against the key tables: every key
// listed, nothing else, each at its table's default.
TEST(ConfigKeys, TheAnnotatedFileListsEveryKeyAtItsTablesDefault) {
  const auto path = test::source_path("config/spinewatch.toml");
  const auto problems = annotated_config_problems(test::read_file(path), "spinewatch.toml");
  EXPECT_TRUE(problems.empty()) << fmt::format("{}", fmt::join(problems, "\n"));
}

// `text` with its line `old_line` replaced by `line` ("" removes it).
std::string with_line(const std::string& text, const std::string& old_line, const std::string& line) {
  const auto at = text.find("\n" + old_line + "\n");
  EXPECT_NE(at, std::string::npos) << old_line;
  if (at == std::string::npos) return text;
  return text.substr(0, at + 1) + (line.empty() ? "" : line + "\n") + text.substr(at + old_line.size() + 2);
}

// The 1-based number of `line` in `text`.
std::size_t line_of(const std::string& text, const std::string& line) {
  const auto at = text.find("\n" + line + "\n");
  return static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at) + 1, '\n')) + 1;
}

// The check fails, naming the key (and the line), when the file omits a
// key, documents one that does not exist, or gives another default.
TEST(ConfigKeys, TheAnnotatedFileCheckFindsAMissingAnUnknownAndAWrongDefault) {
  const std::string text = test::read_file(test::source_path("config/spinewatch.toml"));
  EXPECT_EQ(annotated_config_problems(with_line(text, "threshold = 28", ""), "a.toml"),
            (std::vector<std::string>{
                "a.toml: silhouette.threshold: not listed; the file lists every key with its default (28)"}));
  const std::string extra = with_line(text, "threshold = 28", "threshold = 28\nthreshhold = 28");
  EXPECT_EQ(annotated_config_problems(extra, "a.toml"),
            (std::vector<std::string>{fmt::format("a.toml:{}: silhouette.threshhold: unknown key; did you mean "
                                                  "silhouette.threshold?",
                                                  line_of(text, "threshold = 28") + 1)}));
  const std::string other = with_line(text, "lost_cost = 0.35", "lost_cost = 0.4");
  EXPECT_EQ(annotated_config_problems(other, "a.toml"),
            (std::vector<std::string>{fmt::format("a.toml:{}: cvsm.lost_cost: 0.4 here, but the key's default is 0.35",
                                                  line_of(text, "lost_cost = 0.35"))}));
  const std::string mode = with_line(text, "limbs = \"auto\"", "limbs = \"articulated\"");
  EXPECT_EQ(annotated_config_problems(mode, "a.toml"),
            (std::vector<std::string>{fmt::format(
                "a.toml:{}: cvsm.limbs: \"articulated\" here, but the key's default is \"auto\"",
                line_of(text, "limbs = \"auto\""))}));
}

// Each entry reads and writes its own member: a value other than the
// default, set through the key, changes that key and no other.
TEST(ConfigKeys, EachKeySetsItsOwnMember) {
  const Config defaults;
  for (const OptionKey<Config>& key : config_table()) {
    const OptionValue fallback = key.default_value();
    OptionValue other;
    switch (key.type) {
      case OptionType::Integer:
        other = std::get<long long>(fallback) == key.integer_range.first ? key.integer_range.second
                                                                          : key.integer_range.first;
        break;
      case OptionType::Number:
        other = std::get<double>(fallback) == key.number_range.first ? key.number_range.second : key.number_range.first;
        break;
      case OptionType::Flag: other = !std::get<bool>(fallback); break;
      case OptionType::Text:
      case OptionType::Mode:
        other = key.names.empty() ? std::string("x")
                                  : std::get<std::string>(fallback) == key.names.front() ? key.names.back()
                                                                                          : key.names.front();
        break;
    }
    Config c;
    key.set(c, other);
    EXPECT_EQ(key.get(c), other) << key.name;
    EXPECT_EQ(changed_keys(defaults, c), std::vector<std::string>{key.name}) << key.name;
  }
}

// Every default is a value the loader would take: within the key's range,
// one of its modes.
TEST(ConfigKeys, EveryDefaultIsAValueTheLoaderTakes) {
  for (const OptionKey<Config>& key : config_table()) {
    const OptionValue v = key.default_value();
    switch (key.type) {
      case OptionType::Integer: {
        const long long i = std::get<long long>(v);
        EXPECT_TRUE(i >= key.integer_range.first && i <= key.integer_range.second) << key.name;
        break;
      }
      case OptionType::Number: {
        const double d = std::get<double>(v);
        EXPECT_TRUE((key.zero_is_unknown && d == 0) || (d >= key.number_range.first && d <= key.number_range.second))
            << key.name;
        break;
      }
      case OptionType::Flag: break;
      case OptionType::Text:
      case OptionType::Mode: {
        const std::string& s = std::get<std::string>(v);
        if (!key.names.empty()) {
          EXPECT_NE(std::find(key.names.begin(), key.names.end(), s), key.names.end()) << key.name;
        }
        EXPECT_EQ(parse_config(fmt::format("[{}]\n{} = {}\n", key.name.substr(0, key.name.find('.')),
                                           key.name.substr(key.name.find('.') + 1), toml_text(v)),
                               "d.toml")
                      .ok(),
                  true)
            << key.name;
        break;
      }
    }
  }
}

// What a reload applies without a restart is said once, in the tables
// (docs/daemon.md, "Signals").
TEST(ConfigKeys, TheKeysAReloadAppliesAreTheTablesLiveOnes) {
  std::vector<std::string> live;
  for (const std::string& key : config_keys())
    if (reloadable_key(key)) live.push_back(key);
  EXPECT_EQ(live, (std::vector<std::string>{"station.name", "subject.stature_mm", "subject.mass_kg",
                                            "subject.c7_height_mm", "subject.iliac_crest_height_mm", "alerts.silent",
                                            "log.level", "log.status_interval_s"}));
  EXPECT_FALSE(reloadable_key("no.such_key"));
}

// The estimator runs with the configuration's own sections: nothing is
// copied key by key on the way.
TEST(ConfigKeys, TheEstimatorTakesItsSectionsWhole) {
  auto c = parse_config("[silhouette]\nthreshold = 40\n[cvsm]\nlost_cost = 0.5\n[spine]\nsubsteps = 8\n"
                        "[subject]\nheight_mm = 1600\n[cameras]\nfps = 15\n",
                        "e.toml");
  ASSERT_TRUE(c) << c.error().message;
  const EstimatorOptions o = estimator_options(*c);
  EXPECT_EQ(o.silhouette, c->silhouette);
  EXPECT_EQ(o.cvsm, c->cvsm);
  EXPECT_EQ(o.spine, c->spine);
  EXPECT_EQ(o.subject, c->subject);
  EXPECT_EQ(o.fps, 15.0);
  EXPECT_EQ(o.silhouette.threshold, 40);
}

}  // namespace
}  // namespace spinewatch
