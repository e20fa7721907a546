// BlazePose's lite landmark model run by Arm NN's reference backend on a
// real frame of the shared footage (docs/cvsm.md, "A learned landmark model
// beside the fit"). Skipped where the model (scripts/install-deps) or the
// footage (../shared/data/real) is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

#include <opencv2/videoio.hpp>

#include "spinewatch/landmarks/crop_input.hpp"
#include "spinewatch/landmarks/model_dir.hpp"
#include "spinewatch/landmarks/pose_landmarker.hpp"
#include "test_support.hpp"

namespace lm = spinewatch::landmarks;
namespace test = spinewatch::test;

namespace {
std::string lite_model() { return lm::mediapipe_dir() + "/pose_landmark_lite.tflite"; }
}  // namespace

TEST(LandmarksArmnn, RefusesABackendThatIsNotThere) {
  if (!std::filesystem::exists(lite_model())) GTEST_SKIP() << lite_model() << " is absent (scripts/install-deps)";
  EXPECT_THROW(lm::PoseLandmarker(lite_model(), {"NoSuchBackend"}), std::runtime_error);
}

// caliscope's charuco_calibration, cam_2, frame 20: the man faces the
// camera, his head within x 700–870, y 200–420 of the 1280×720 frame (its
// top at y 210), his chest at (760, 520), his belly at (780, 700), his left
// forearm at (990, 650), the white door on the left at (150, 300), the
// doorway above-left of his head at (700, 230) and the wall above it at
// (760, 180) (read off the frame by eye). Without the resizes' half-pixel
// sampling (tflite_resize.hpp) the mask lay up and left of him: it held the
// doorway and the wall above his head and missed his belly and forearm. The crop is a square about his hips, as MediaPipe's
// pose graph makes it (the body's extent × 1.25 about the hips; chosen by
// hand here, the detector does not run under Arm NN 20.08).
TEST(LandmarksArmnn, LandsOnTheManInARealFrame) {
  if (!std::filesystem::exists(lite_model())) GTEST_SKIP() << lite_model() << " is absent (scripts/install-deps)";
  const std::string video = test::source_path("../shared/data/real/caliscope/charuco_calibration/cam_2.mp4");
  if (!std::filesystem::exists(video)) GTEST_SKIP() << video << " is absent (the shared real footage)";
  cv::VideoCapture capture(video);
  capture.set(cv::CAP_PROP_POS_FRAMES, 20);
  cv::Mat frame;
  ASSERT_TRUE(capture.read(frame));
  const lm::SquareCrop crop{5, 75, 1550};

  lm::PoseLandmarker landmarker(lite_model(), {"CpuRef"});
  const lm::PoseOutput out = landmarker.infer(lm::crop_to_input(frame, crop, lm::kInputSide));

  EXPECT_GT(out.presence_score, 0.5f);
  const cv::Point2f nose = crop.to_frame(out.landmarks[0].x, out.landmarks[0].y, lm::kInputSide);
  EXPECT_TRUE(cv::Rect2f(700, 200, 170, 220).contains(nose)) << nose;
  const cv::Mat mask = lm::mask_to_frame(out.mask, lm::kInputSide, crop, frame.size(), 0.5f);
  EXPECT_EQ(mask.at<std::uint8_t>(520, 760), 255) << "chest";
  EXPECT_EQ(mask.at<std::uint8_t>(700, 780), 255) << "belly";
  EXPECT_EQ(mask.at<std::uint8_t>(650, 990), 255) << "forearm";
  EXPECT_EQ(mask.at<std::uint8_t>(300, 150), 0) << "door";
  EXPECT_EQ(mask.at<std::uint8_t>(230, 700), 0) << "doorway beside his head";
  EXPECT_EQ(mask.at<std::uint8_t>(180, 760), 0) << "wall above his head";
}
