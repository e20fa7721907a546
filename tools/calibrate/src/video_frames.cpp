#include "spinewatch/calibrate/video_frames.hpp"

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "spinewatch/media/media_files.hpp"

namespace spinewatch {

Result<VideoFrames> read_video(const std::filesystem::path& path, int step) {
  if (!std::filesystem::is_regular_file(path))
    return Error{fmt::format("{}: no such video file", path.string())};
  VideoFrames out;
  try {
    auto reader = media::open_video(path);
    if (!reader) return reader.error();
    media::VideoReader& capture = **reader;
    if (!capture.opened())
      return Error{fmt::format("{}: cannot be read as a video (OpenCV's FFmpeg reader: an MP4, MKV or AVI of "
                               "H.264, MJPEG …)",
                               path.string())};
    out.fps = capture.fps();
    cv::Mat frame;
    for (int index = 0; capture.read(frame); ++index) {
      if (index % step != 0) continue;
      cv::Mat grey;
      if (frame.channels() == 1)
        grey = frame.clone();
      else
        cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
      out.grey.push_back(std::move(grey));
    }
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{}: {}", path.string(), e.err)};
  }
  if (out.grey.empty()) return Error{fmt::format("{}: no frame could be decoded", path.string())};
  out.size = out.grey.front().size();
  return out;
}

}  // namespace spinewatch
