// cvsm.model and spine.model (issue 17: keys that had no effect): the
// station's TOML names a model file → the estimator fits with it. A copy
// of the built-in file gives exactly the built-in results; a changed copy
// changes the postures; a file that cannot be read or parsed is one error
// naming the key and the file.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/estimator_options.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/phantom/phantom.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

// Per pair: the state, the fit cost and T1…L5 (mm, rounded to 0.01).
std::vector<std::string> postures_with(const std::string& toml) {
  auto config = parse_config(toml, "test.toml");
  EXPECT_TRUE(config) << config.error().message;
  auto options = load_estimator_options(*config);
  EXPECT_TRUE(options) << options.error().message;
  phantom::PhantomOptions po;
  po.scenario = "flexion";
  po.frames = 20;
  auto seq = phantom::PhantomSequence::create(po);
  EXPECT_TRUE(seq) << seq.error().message;
  PostureEstimator estimator(seq->options().rig, *options);
  std::vector<std::string> out;
  for (int i = 0; i < seq->frame_count(); ++i) {
    const Posture p = estimator.process(phantom::grey_pair(seq->render(i)));
    std::string line = fmt::format("{} {}", to_string(p.state), p.fit.cost);
    if (p.vertebrae)
      for (const auto& v : *p.vertebrae) line += fmt::format(" {:.2f} {:.2f} {:.2f}", v.body_center.x(), v.body_center.y(), v.body_center.z());
    out.push_back(std::move(line));
  }
  return out;
}

constexpr const char* kGenericPlacement = "[subject]\nspine_placement = \"generic\"\n";

std::string with_model(const char* key, const std::filesystem::path& file) {
  // The phantom's generic subject carries the generic spine placement.
  return fmt::format("{}[{}]\nmodel = \"{}\"\n", kGenericPlacement, key, file.string());
}

// Every line "NAME = number" scaled by `factor`.
std::string scaled(const std::string& text, const std::string& name, double factor) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(name + " = ", 0) == 0) line = fmt::format("{} = {}", name, factor * std::stod(line.substr(name.size() + 3)));
    out += line;
    out += '\n';
  }
  return out;
}

class ModelKeys : public ::testing::Test {
 protected:
  // A copy of a shipped model file, with `edit` applied to its text.
  std::filesystem::path copy_of(const char* shipped, const std::function<std::string(std::string)>& edit) {
    const auto path = dir.path() / (std::to_string(copies++) + ".toml");
    test::write_file(path, edit(test::read_file(test::source_path(shipped))));
    return path;
  }
  test::TempDir dir;
  int copies = 0;
};

std::string same(std::string s) { return s; }

TEST_F(ModelKeys, CvsmModelFileIsWhatTheFitUses) {
  const auto built_in = postures_with(kGenericPlacement);
  ASSERT_FALSE(built_in.empty());
  EXPECT_EQ(postures_with(with_model("cvsm", copy_of("config/cvsm-generic.toml", same))), built_in)
      << "the shipped file is the built-in model";
  // Every trunk section a quarter wider.
  const auto wider = copy_of("config/cvsm-generic.toml", [](std::string s) { return scaled(s, "half_width", 1.25); });
  EXPECT_NE(postures_with(with_model("cvsm", wider)), built_in);
}

TEST_F(ModelKeys, SpineModelFileIsWhatTheSpineIsBuiltFrom) {
  const auto built_in = postures_with(kGenericPlacement);
  EXPECT_EQ(postures_with(with_model("spine", copy_of("config/spine-generic.toml", same))), built_in);
  const auto flatter = copy_of("config/spine-generic.toml", [](std::string s) { return scaled(s, "kyphosis_deg", 0.5); });
  EXPECT_NE(postures_with(with_model("spine", flatter)), built_in);
}

TEST_F(ModelKeys, AFileThatCannotBeReadOrParsedIsOneErrorNamingKeyAndFile) {
  auto missing = parse_config("[cvsm]\nmodel = \"/nonexistent/cvsm.toml\"\n", "s.toml");
  ASSERT_TRUE(missing);
  auto r = load_estimator_options(*missing);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, "cvsm.model: /nonexistent/cvsm.toml: cannot open: No such file or directory");

  const auto broken = copy_of("config/spine-generic.toml", [](std::string s) {
    return s.replace(s.find("kyphosis_deg = 40.0"), 19, "kyphosis_deg = \"steep\"");
  });
  auto bad = parse_config(fmt::format("[spine]\nmodel = \"{}\"\n", broken.string()), "s.toml");
  ASSERT_TRUE(bad);
  auto b = load_estimator_options(*bad);
  ASSERT_FALSE(b);
  EXPECT_EQ(b.error().message.rfind("spine.model: " + broken.string(), 0), 0u) << b.error().message;
  EXPECT_NE(b.error().message.find("kyphosis_deg"), std::string::npos) << b.error().message;
}

}  // namespace
}  // namespace spinewatch
