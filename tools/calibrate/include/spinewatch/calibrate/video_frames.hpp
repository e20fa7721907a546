#pragma once
// spinewatch calibrate --frontal-video/--lateral-video: the board's views
// from a video file per camera (what other tools record: caliscope's
// cam_N.mp4, a phone's clip), read at their own resolution.
#include <filesystem>
#include <vector>

#include <opencv2/core.hpp>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct VideoFrames {
  std::vector<cv::Mat> grey;  // CV_8U, every `step`-th frame
  cv::Size size;
  double fps = 0;
};

// Every `step`-th frame of a video (cv::VideoCapture, FFmpeg), as grey
// images. An Error names the file when it cannot be opened or has no frame.
Result<VideoFrames> read_video(const std::filesystem::path& path, int step = 1);

}  // namespace spinewatch
