#include "spinewatch/import/video_clip.hpp"

#include <optional>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "spinewatch/media/media_files.hpp"

namespace spinewatch::import {
namespace {

// A change of more than this many grey levels in a cell's mean is motion
// (H.264 noise on a still scene stays within a few).
constexpr int kChangeLevels = 12;

}  // namespace

VideoClip::VideoClip(VideoClip&&) noexcept = default;
VideoClip& VideoClip::operator=(VideoClip&&) noexcept = default;
VideoClip::~VideoClip() = default;

Result<VideoClip> VideoClip::open(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) return Error{fmt::format("{}: no such file", file)};
  VideoClip clip;
  clip.path_ = path;
  try {
    auto reader = media::open_video(path);
    if (!reader) return reader.error();
    clip.capture_ = std::move(*reader);
    if (!clip.capture_->opened())
      return Error{fmt::format("{}: not a video OpenCV's FFmpeg backend can read (mp4/H.264, avi, mkv, …)", file)};
    cv::Mat first;
    if (!clip.capture_->read(first) || first.empty())
      return Error{fmt::format("{}: no frame could be decoded", file)};
    if (first.type() != CV_8UC3)
      return Error{fmt::format("{}: decodes to {}-channel images, expected 8-bit colour", file, first.channels())};
    clip.width_ = first.cols;
    clip.height_ = first.rows;
    clip.fps_ = clip.capture_->fps();
    if (auto s = clip.rewind(); !s) return s.error();
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{}: OpenCV could not read it ({})", file, e.err)};
  }
  return clip;
}

Status VideoClip::rewind() {
  // Reopening is exact where seeking an H.264 stream to 0 may not be.
  auto reader = media::open_video(path_);
  if (!reader) return reader.error();
  capture_ = std::move(*reader);
  if (!capture_->opened()) return Error{fmt::format("{}: could not be reopened", path_.string())};
  return Ok{};
}

bool VideoClip::next(cv::Mat& bgr) {
  if (!capture_->read(bgr) || bgr.empty()) return false;
  return bgr.cols == width_ && bgr.rows == height_ && bgr.type() == CV_8UC3;
}

Status VideoClip::skip(int n) {
  for (int i = 0; i < n; ++i)
    if (!capture_->grab()) return Error{fmt::format("{}: ended while skipping {} frames", path_.string(), n)};
  return Ok{};
}

Result<int> VideoClip::scan(MotionMap* motion) {
  cv::Mat bgr, grey, small, previous;
  int frames = 0;
  if (motion) {
    motion->changed = cv::Mat::zeros((height_ + motion->cell - 1) / motion->cell,
                                     (width_ + motion->cell - 1) / motion->cell, CV_32S);
    motion->frames = 0;
  }
  try {
    while (capture_->read(bgr) && !bgr.empty()) {
      if (bgr.cols != width_ || bgr.rows != height_)
        return Error{fmt::format("{}: frame {} is {}x{}, the first was {}x{}", path_.string(), frames, bgr.cols,
                                 bgr.rows, width_, height_)};
      ++frames;
      if (!motion) continue;
      cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
      cv::resize(grey, small, motion->changed.size(), 0, 0, cv::INTER_AREA);
      if (!previous.empty()) {
        cv::Mat diff, moved;
        cv::absdiff(small, previous, diff);
        cv::compare(diff, kChangeLevels, moved, cv::CMP_GT);  // 255 where moved
        cv::Mat ones;
        moved.convertTo(ones, CV_32S, 1.0 / 255.0);
        motion->changed += ones;
        ++motion->frames;
      }
      small.copyTo(previous);
    }
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{}: decoding failed after {} frames ({})", path_.string(), frames, e.err)};
  }
  if (auto s = rewind(); !s) return s.error();
  return frames;
}

std::optional<Box> motion_box(const MotionMap& motion) {
  if (motion.changed.empty()) return std::nullopt;
  const int rows = motion.changed.rows, cols = motion.changed.cols;
  std::vector<double> across(static_cast<std::size_t>(cols), 0.0), down(static_cast<std::size_t>(rows), 0.0);
  double total = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double v = motion.changed.at<int>(r, c);
      across[static_cast<std::size_t>(c)] += v;
      down[static_cast<std::size_t>(r)] += v;
      total += v;
    }
  if (total <= 0) return std::nullopt;
  auto trimmed = [total](const std::vector<double>& mass, int& lo, int& hi) {
    double run = 0;
    lo = 0;
    while (lo + 1 < static_cast<int>(mass.size()) && run + mass[static_cast<std::size_t>(lo)] < 0.02 * total)
      run += mass[static_cast<std::size_t>(lo++)];
    run = 0;
    hi = static_cast<int>(mass.size()) - 1;
    while (hi > lo && run + mass[static_cast<std::size_t>(hi)] < 0.02 * total) run += mass[static_cast<std::size_t>(hi--)];
  };
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  trimmed(across, x0, x1);
  trimmed(down, y0, y1);
  return Box{x0 * motion.cell, y0 * motion.cell, (x1 - x0 + 1) * motion.cell, (y1 - y0 + 1) * motion.cell};
}

}  // namespace spinewatch::import
