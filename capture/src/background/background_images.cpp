#include "spinewatch/capture/background_images.hpp"

#include <system_error>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

namespace spinewatch {
namespace {

Result<GreyImage> read_grey(const std::filesystem::path& path, int width, int height) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{fmt::format("{}: no such file", path.string())};
  // IMREAD_GRAYSCALE turns colour into its luma (BT.601), which is what
  // the Y of a YUYV frame holds.
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  if (image.empty() || image.type() != CV_8U)
    return Error{fmt::format("{}: cannot be read as an 8-bit image", path.string())};
  if (width > 0 && (image.cols != width || image.rows != height))
    return Error{fmt::format("{}: {}x{} does not match the cameras' {}x{}", path.string(), image.cols, image.rows,
                             width, height)};
  GreyImage out{image.cols, image.rows, {}};
  out.pixels.reserve(image.total());
  for (int y = 0; y < image.rows; ++y) out.pixels.insert(out.pixels.end(), image.ptr(y), image.ptr(y) + image.cols);
  return out;
}

}  // namespace

bool has_background_images(const std::filesystem::path& dir) {
  std::error_code ec;
  return std::filesystem::exists(dir / kBackgroundFiles[0], ec) && std::filesystem::exists(dir / kBackgroundFiles[1], ec);
}

Result<BackgroundImages> load_background_images(const std::filesystem::path& frontal,
                                                const std::filesystem::path& lateral, int expected_width,
                                                int expected_height) {
  auto f = read_grey(frontal, expected_width, expected_height);
  if (!f) return f.error();
  auto l = read_grey(lateral, f->width, f->height);
  if (!l) return l.error();
  return BackgroundImages{std::move(f).value(), std::move(l).value()};
}

Result<BackgroundImages> load_background_images(const std::filesystem::path& dir, int expected_width,
                                                int expected_height) {
  return load_background_images(dir / kBackgroundFiles[0], dir / kBackgroundFiles[1], expected_width, expected_height);
}

Status write_background_images(const std::filesystem::path& dir, const BackgroundImages& images) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error{fmt::format("{}: {}", dir.string(), ec.message())};
  const GreyImage* views[2] = {&images.frontal, &images.lateral};
  for (std::size_t v = 0; v < 2; ++v) {
    const GreyImage& g = *views[v];
    const auto path = dir / kBackgroundFiles[v];
    if (g.width <= 0 || g.height <= 0 || g.pixels.size() != std::size_t(g.width) * std::size_t(g.height))
      return Error{fmt::format("{}: empty image", path.string())};
    const cv::Mat image(g.height, g.width, CV_8U, const_cast<std::uint8_t*>(g.pixels.data()));
    bool written = false;
    try {
      written = cv::imwrite(path.string(), image);
    } catch (const cv::Exception& e) {
      return Error{fmt::format("{}: {}", path.string(), e.what())};
    }
    if (!written) return Error{fmt::format("{}: cannot be written", path.string())};
  }
  return Ok{};
}

}  // namespace spinewatch
