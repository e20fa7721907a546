// The TfLite float16 fold (tools/landmarks, docs/cvsm.md "A learned landmark
// model beside the fit"): the half-precision conversion exactly, malformed
// input refused, and the fold on the model @mediapipe/pose ships (skipped
// where scripts/install-deps has not installed it).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "spinewatch/landmarks/model_dir.hpp"
#include "spinewatch/landmarks/tflite_fold.hpp"
#include "spinewatch/landmarks/tflite_resize.hpp"

namespace lm = spinewatch::landmarks;

TEST(LandmarksFold, HalfToFloatIsExact) {
  EXPECT_EQ(lm::half_to_float(0x3C00), 1.0f);
  EXPECT_EQ(lm::half_to_float(0xC000), -2.0f);
  EXPECT_EQ(lm::half_to_float(0x3555), 0.333251953125f);
  EXPECT_EQ(lm::half_to_float(0x7BFF), 65504.0f);                // largest half
  EXPECT_EQ(lm::half_to_float(0x0001), std::ldexp(1.0f, -24));   // smallest subnormal
  EXPECT_EQ(lm::half_to_float(0x03FF), 1023.0f * std::ldexp(1.0f, -24));  // largest subnormal
  EXPECT_EQ(lm::half_to_float(0x0400), std::ldexp(1.0f, -14));   // smallest normal
  EXPECT_TRUE(std::signbit(lm::half_to_float(0x8000)));
  EXPECT_EQ(lm::half_to_float(0x7C00), std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isnan(lm::half_to_float(0x7E00)));
}

TEST(LandmarksFold, RefusesWhatIsNotATfliteModel) {
  std::vector<std::uint8_t> text{'n', 'o', 't', ' ', 'a', ' ', 'm', 'o', 'd', 'e', 'l', '!'};
  EXPECT_THROW(lm::fold_float16_weights(text), lm::ModelFormatError);
  // The identifier right, the root offset past the end: refused, not read.
  std::vector<std::uint8_t> truncated{0xff, 0xff, 0, 0, 'T', 'F', 'L', '3'};
  EXPECT_THROW(lm::fold_float16_weights(truncated), lm::ModelFormatError);
}

TEST(LandmarksFold, FoldsTheShippedModelOnce) {
  const std::string path = lm::mediapipe_dir() + "/pose_landmark_lite.tflite";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent (scripts/install-deps)";
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> model{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const std::size_t original = model.size();

  const lm::FoldReport first = lm::fold_float16_weights(model);
  EXPECT_GT(first.dequantize_folded, 0u);
  EXPECT_GT(first.operators_left, 0u);
  // Only appended: the float32 data, its length words and alignment padding.
  EXPECT_GE(model.size(), original + first.float32_bytes_added);
  EXPECT_LE(model.size(), original + first.float32_bytes_added + 20 * first.dequantize_folded);

  // Folded, nothing is left to fold and no operator is lost.
  const lm::FoldReport second = lm::fold_float16_weights(model);
  EXPECT_EQ(second.dequantize_folded, 0u);
  EXPECT_EQ(second.operators_left, first.operators_left);

  // The segmentation head's upsamplings ask for half-pixel sampling, before
  // the fold and after it (the fold keeps them, at their new indices).
  const auto resizes = lm::half_pixel_resizes(model);
  EXPECT_FALSE(resizes.empty());
  EXPECT_LT(*resizes.rbegin(), first.operators_left);
}

TEST(LandmarksFold, HalfPixelResizesRefusesATruncatedModel) {
  std::vector<std::uint8_t> truncated{0xff, 0xff, 0, 0, 'T', 'F', 'L', '3'};
  EXPECT_THROW(lm::half_pixel_resizes(truncated), lm::ModelFormatError);
}
