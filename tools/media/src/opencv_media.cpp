// spinewatch-media.so: the module that links OpenCV's videoio and
// imgcodecs (media_files.hpp says why they are apart).
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "module_abi.hpp"

namespace spinewatch::media {
namespace {

class OpenCvVideoReader final : public VideoReader {
 public:
  explicit OpenCvVideoReader(const std::string& path) : capture_(path, cv::CAP_FFMPEG) {}
  bool opened() const override { return capture_.isOpened(); }
  bool read(cv::Mat& frame) override { return capture_.read(frame); }
  bool grab() override { return capture_.grab(); }
  double fps() const override { return capture_.get(cv::CAP_PROP_FPS); }

 private:
  cv::VideoCapture capture_;
};

std::unique_ptr<VideoReader> open_video(const std::string& path) { return std::make_unique<OpenCvVideoReader>(path); }
cv::Mat read_image(const std::string& path, int flags) { return cv::imread(path, flags); }
bool write_image(const std::string& path, const cv::Mat& image, const std::vector<int>& params) {
  return cv::imwrite(path, image, params);
}

constexpr ModuleFunctions kFunctions{sizeof(ModuleFunctions), open_video, read_image, write_image};

}  // namespace
}  // namespace spinewatch::media

extern "C" __attribute__((visibility("default"))) const spinewatch::media::ModuleFunctions* spinewatch_media_functions() {
  return &spinewatch::media::kFunctions;
}
