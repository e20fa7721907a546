#pragma once
// Video and image files for the CLI's file-facing commands (import,
// calibrate --frontal-video, phantom --backdrop, replay --overlay,
// calibrate --write-board), read and written by OpenCV's videoio and
// imgcodecs in a module of their own, spinewatch-media.so, loaded the
// first time one of these is called.
//
// Why a module: videoio and imgcodecs bring about 220 shared libraries
// (FFmpeg, GStreamer, GDAL, GDCM, …) into every process that links them,
// and loading and relocating them made every start of the CLI take 0.3 s
// (0.6 s under the sanitizers) where most commands never open a video or
// an image (docs/architecture.md, "The media module").
#include <filesystem>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::media {

// One video file's frames in order, as cv::VideoCapture with the FFmpeg
// backend reads them (mp4/H.264, avi, mkv, …). The module's own errors
// are OpenCV's: a cv::Exception may leave read() and grab().
class VideoReader {
 public:
  virtual ~VideoReader() = default;
  virtual bool opened() const = 0;
  virtual bool read(cv::Mat& frame) = 0;  // the next frame (8-bit BGR); false at the end
  virtual bool grab() = 0;                // decodes the next frame and drops it
  virtual double fps() const = 0;         // as the container says
};

// The media module's functions (an Error only when the module itself
// cannot be loaded: its message names the file and the fix).
// open_video: a reader even when OpenCV cannot open the file (opened()
// says so), as cv::VideoCapture does.
Result<std::unique_ptr<VideoReader>> open_video(const std::filesystem::path& path);
// read_image: cv::imread(path, flags); an empty image when OpenCV cannot read it.
Result<cv::Mat> read_image(const std::filesystem::path& path, int flags);
// write_image: cv::imwrite(path, image, params); false when OpenCV could not write it.
Result<bool> write_image(const std::filesystem::path& path, const cv::Mat& image, const std::vector<int>& params = {});

// Where the module is looked for by this process: the build tree's copy
// when the running program is one of that build tree's, otherwise the
// installed one beside the program (<bindir>/../lib/<arch>/spinewatch/).
std::filesystem::path module_path();

}  // namespace spinewatch::media
