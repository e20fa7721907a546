// Every [silhouette] key has an effect: the station's TOML → estimator
// options → PostureEstimator on a synthetic scene built to exercise the
// key; what the estimator then does (silhouettes, states, flags, its
// background and counters) differs from the defaults. The stored-image
// keys (background_frontal/_lateral) are exercised on the real daemon in
// tests/e2e (DaemonE2E.*Background*).
#include <map>
#include <random>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "../estimator/silhouette/synthetic_scene.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/estimator_options.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch {
namespace {

using namespace test::synthetic;

// One frame of the scene, both views alike: grey (CV_8U) or YUYV (CV_8UC2:
// Y, then U or V, per pixel, which is YUYV's memory layout).
using Scene = cv::Mat (*)(int frame, std::mt19937& rng);

// What the estimator did, frame by frame, that a key could change.
struct Observed {
  std::vector<std::int64_t> silhouette_px;
  std::vector<std::string> states;
  std::vector<std::uint8_t> final_background;
  BackgroundCounts counts;
  bool operator==(const Observed& o) const {
    return silhouette_px == o.silhouette_px && states == o.states && final_background == o.final_background &&
           counts.updates == o.counts.updates && counts.relearns == o.counts.relearns &&
           counts.bootstraps == o.counts.bootstraps;
  }
};

Observed run(const std::string& silhouette_toml, const Scene& scene, int frames) {
  auto config = parse_config("[silhouette]\n" + silhouette_toml + "\n", "test.toml");
  EXPECT_TRUE(config) << config.error().message;
  PostureEstimator estimator(CameraRig::default_rig(), estimator_options(*config));
  std::mt19937 rng(11);
  Observed o;
  for (int i = 0; i < frames; ++i) {
    const cv::Mat image = scene(i, rng);
    std::vector<std::uint8_t> bytes(image.datastart, image.dataend);
    const FrameFormat format = FrameFormat::packed(image.type() == CV_8UC2 ? PixelFormat::YUYV : PixelFormat::GREY, kW, kH);
    FramePair pair{static_cast<std::uint64_t>(i), i * 33'333'333LL, Frame::copy_of(format, {}, bytes),
                   Frame::copy_of(format, {}, bytes)};
    const Posture p = estimator.process(pair);
    const EstimatorTrace t = estimator.last_trace();
    o.silhouette_px.push_back(t.silhouette[0] ? t.silhouette[0]->count() : -1);
    o.states.push_back(std::string(to_string(p.state)) + "/" + p.fit.flag.value_or(""));
    o.counts = p.background;
    if (t.background[0]) o.final_background = *t.background[0];
  }
  return o;
}

const cv::Mat kWall = smooth_background();
const cv::Mat kNobody(kH, kW, CV_8U, cv::Scalar(0));

// Empty for 20 frames, then the person walks in and sways; the light
// drifts unevenly throughout.
cv::Mat walk_in(int i, std::mt19937& rng) {
  cv::Mat lit(kWall.size(), CV_8U);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      lit.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(kWall.at<std::uint8_t>(y, x) * (1.0 - 0.002 * i * x / kW));
  return compose(lit, i < 20 ? kNobody : person_mask(static_cast<int>(10 * std::sin(i * 0.2))), 1.0, 2.0, rng);
}

// The person in view from the first frame, moving side to side.
cv::Mat in_view(int i, std::mt19937& rng) {
  return compose(kWall, person_mask(static_cast<int>(40 * std::sin(i * 2 * M_PI / 60))), 1.0, 2.0, rng);
}

// The person, then an empty scene with a lamp switched on.
cv::Mat leaves(int i, std::mt19937& rng) {
  if (i < 20) return compose(kWall, person_mask(), 1.0, 2.0, rng);
  cv::Mat lamp;
  kWall.convertTo(lamp, CV_8U, 1.1);
  return compose(lamp, kNobody, 1.0, 2.0, rng);
}

cv::Mat yuyv_mat(const YuyvImage& image) { return cv::Mat(kH, kW, CV_8UC2, const_cast<std::uint8_t*>(image.bytes.data())).clone(); }

// Colour: empty for 20 frames, then a person in a blue shirt as bright as
// the beige wall walks in (only the chroma shows them).
cv::Mat camouflaged(int i, std::mt19937& rng) {
  ColourScene scene;
  scene.person_luma = -1;
  const cv::Mat person = i < 20 ? kNobody : person_mask(static_cast<int>(10 * std::sin(i * 0.2)));
  return yuyv_mat(compose_colour(kWall, person, cv::Mat(), scene, rng));
}

// Colour: empty for 20 frames, then a person with their shadow beside them.
cv::Mat with_shadow(int i, std::mt19937& rng) {
  const cv::Mat person = i < 20 ? kNobody : person_mask(static_cast<int>(10 * std::sin(i * 0.2)));
  cv::Mat shadow;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 30, 0, 1, 10);
  cv::warpAffine(person, shadow, shift, person.size());
  return yuyv_mat(compose_colour(kWall, person, shadow, ColourScene{}, rng));
}

struct KeyCase {
  const char* toml;
  Scene scene;
  int frames;
  const char* base;  // other keys set in both runs
};
void PrintTo(const KeyCase& c, std::ostream* os) { *os << c.toml; }

class SilhouetteKey : public ::testing::TestWithParam<KeyCase> {};

// The run with the defaults, once per scene in the process: the suite runs
// as one process (tests/daemon/CMakeLists.txt), and seven of its cases
// share one scene.
const Observed& default_run(const KeyCase& c) {
  static std::map<std::tuple<std::string, Scene, int>, Observed> runs;
  const auto key = std::make_tuple(std::string(c.base), c.scene, c.frames);
  auto it = runs.find(key);
  if (it == runs.end()) it = runs.emplace(key, run(c.base, c.scene, c.frames)).first;
  return it->second;
}

TEST_P(SilhouetteKey, ChangesWhatTheEstimatorDoes) {
  const KeyCase& c = GetParam();
  const Observed& with_default = default_run(c);
  const Observed changed = run(std::string(c.base) + "\n" + c.toml, c.scene, c.frames);
  EXPECT_FALSE(changed == with_default) << c.toml << " made no difference; last state " << changed.states.back()
                                        << ", updates " << changed.counts.updates << ", relearns "
                                        << changed.counts.relearns << ", bootstraps " << changed.counts.bootstraps;
}

INSTANTIATE_TEST_SUITE_P(
    Keys, SilhouetteKey,
    ::testing::Values(KeyCase{"background = \"threshold\"", walk_in, 60, ""},
                      KeyCase{"learn_frames = 15", walk_in, 60, ""},
                      KeyCase{"threshold = 120", walk_in, 60, ""},
                      KeyCase{"chroma_threshold = 0", camouflaged, 40, ""},
                      KeyCase{"shadow_ratio = 1.0", with_shadow, 40, ""},
                      KeyCase{"min_blob_px = 20000", walk_in, 60, ""},
                      KeyCase{"adapt_s = 0", walk_in, 60, ""},
                      KeyCase{"adapt_margin_px = 0", walk_in, 60, ""},
                      KeyCase{"relearn_empty_s = 1", leaves, 90, ""},
                      KeyCase{"bootstrap = false", in_view, 60, ""}),
    [](const auto& info) {
      std::string name = info.param.toml;
      return name.substr(0, name.find(' '));
    });

// background = "image" with nothing given says so instead of learning.
TEST(SilhouetteKeys, ImageModeWithoutImagesIsNoBackground) {
  const Observed o = run("background = \"image\"", walk_in, 5);
  for (const auto& s : o.states) EXPECT_EQ(s, "init/no_background");
}

}  // namespace
}  // namespace spinewatch
