#pragma once
// One camera's video file, decoded by OpenCV's videoio (the media module) (FFmpeg on Debian:
// mp4/H.264, avi, mkv, …): its size and rate, a first pass that counts
// its frames and where it moves, then its frames in order.
#include <filesystem>
#include <memory>
#include <optional>

#include <opencv2/core.hpp>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::media {
class VideoReader;
}

namespace spinewatch::import {

// Where the clip moved: per cell of a coarse grid, in how many frames it
// changed by more than a threshold from the frame before.
struct MotionMap {
  int cell = 8;      // source pixels per cell side
  cv::Mat changed;   // CV_32S, counts
  int frames = 0;    // frames compared
};

class VideoClip {
 public:
  static Result<VideoClip> open(const std::filesystem::path& path);
  VideoClip(VideoClip&&) noexcept;
  VideoClip& operator=(VideoClip&&) noexcept;
  ~VideoClip();

  int width() const { return width_; }
  int height() const { return height_; }
  double fps() const { return fps_; }
  const std::filesystem::path& path() const { return path_; }

  // Decodes the whole clip once: its frame count (what was decoded, not
  // what the container claims) and its motion. Leaves the clip at its start.
  Result<int> scan(MotionMap* motion);
  // The next frame (8-bit BGR), or false at the end.
  bool next(cv::Mat& bgr);
  // Decodes and drops `n` frames.
  Status skip(int n);

 private:
  VideoClip() = default;
  Status rewind();
  std::filesystem::path path_;
  std::unique_ptr<media::VideoReader> capture_;
  int width_ = 0, height_ = 0;
  double fps_ = 0;
};

// The part of the frame that moved during the clip: the box holding the
// middle 96 % (2 % trimmed off each side, across and down) of the cells'
// change counts, in source pixels; nothing when nothing moved.
struct Box {
  int x = 0, y = 0, width = 0, height = 0;
};
std::optional<Box> motion_box(const MotionMap& motion);

}  // namespace spinewatch::import
