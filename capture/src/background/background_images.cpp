#include "spinewatch/capture/background_images.hpp"

#include <algorithm>
#include <system_error>
#include <utility>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "background/png_file.hpp"

namespace spinewatch {
namespace {

// A colour image as YUYV: Y of each pixel, Cb and Cr averaged over each pair.
std::vector<std::uint8_t> yuyv_of(const cv::Mat& bgr) {
  cv::Mat ycrcb;
  cv::cvtColor(bgr, ycrcb, cv::COLOR_BGR2YCrCb);
  std::vector<std::uint8_t> out(ycrcb.total() * 2);
  std::size_t k = 0;
  for (int y = 0; y < ycrcb.rows; ++y) {
    const cv::Vec3b* row = ycrcb.ptr<cv::Vec3b>(y);
    for (int x = 0; x + 1 < ycrcb.cols; x += 2, k += 4) {
      out[k] = row[x][0];
      out[k + 1] = static_cast<std::uint8_t>((row[x][2] + row[x + 1][2] + 1) / 2);  // U = Cb
      out[k + 2] = row[x + 1][0];
      out[k + 3] = static_cast<std::uint8_t>((row[x][1] + row[x + 1][1] + 1) / 2);  // V = Cr
    }
  }
  return out;
}

cv::Mat bgr_of(const SceneImage& image) {
  cv::Mat ycrcb(image.height, image.width, CV_8UC3);
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* in = image.pixels.data() + static_cast<std::ptrdiff_t>(y) * image.width * 2;
    cv::Vec3b* row = ycrcb.ptr<cv::Vec3b>(y);
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* pair = in + 4 * (x / 2);
      row[x] = {in[2 * x], pair[3], pair[1]};  // Y, Cr = V, Cb = U
    }
  }
  cv::Mat bgr;
  cv::cvtColor(ycrcb, bgr, cv::COLOR_YCrCb2BGR);
  return bgr;
}

// The largest scene a camera delivers (config: cameras.width/height <= 4096).
constexpr std::uint32_t kMaxSide = 4096;

// The size is the PNG header's, checked before anything is decoded: a
// crafted header (a valid checksum over 30000x30000) would otherwise have
// the decoder's buffer asked for gigabytes. Only PNG is read
// (docs/interfaces.md §2).
Result<SceneImage> read_scene(const std::filesystem::path& path, int width, int height) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{fmt::format("{}: no such file", path.string())};
  auto file = PngFile::open(path);
  if (!file) return file.error();
  const std::uint32_t declared_width = file->width(), declared_height = file->height();
  if (width > 0 && (declared_width != std::uint32_t(width) || declared_height != std::uint32_t(height)))
    return Error{fmt::format("{}: {}x{} does not match the cameras' {}x{}", path.string(), declared_width,
                             declared_height, width, height)};
  if (declared_width == 0 || declared_height == 0 || declared_width > kMaxSide || declared_height > kMaxSide)
    return Error{fmt::format("{}: {}x{} is not a camera's size (1..{} a side)", path.string(), declared_width,
                             declared_height, kMaxSide)};
  if (file->deep()) return Error{fmt::format("{}: cannot be read as an 8-bit grey or colour image", path.string())};
  auto decoded = file->decode();
  if (!decoded) return decoded.error();
  cv::Mat image = std::move(decoded).value();
  if (image.channels() == 3 && image.cols % 2 == 0) return SceneImage{image.cols, image.rows, 2, yuyv_of(image)};
  // Grey, or colour of an odd width (no pixel pairs): its luma (BT.601,
  // which is what the Y of a YUYV frame holds).
  if (image.channels() == 3) cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
  SceneImage out{image.cols, image.rows, 1, {}};
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
  auto f = read_scene(frontal, expected_width, expected_height);
  if (!f) return f.error();
  auto l = read_scene(lateral, f->width, f->height);
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
  const SceneImage* views[2] = {&images.frontal, &images.lateral};
  for (std::size_t v = 0; v < 2; ++v) {
    const SceneImage& g = *views[v];
    const auto path = dir / kBackgroundFiles[v];
    if (g.width <= 0 || g.height <= 0 || (g.step != 1 && g.step != 2) || (g.colour() && g.width % 2 != 0) ||
        g.pixels.size() != std::size_t(g.width) * std::size_t(g.height) * std::size_t(g.step))
      return Error{fmt::format("{}: empty image", path.string())};
    const cv::Mat image = g.colour() ? bgr_of(g) : cv::Mat(g.height, g.width, CV_8U, const_cast<std::uint8_t*>(g.pixels.data()));
    if (auto written = write_png(path, image); !written) return written.error();
  }
  return Ok{};
}

}  // namespace spinewatch
