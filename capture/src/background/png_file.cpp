#include "background/png_file.hpp"

#include <array>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>
#include <png.h>

#include "spinewatch/frames/printable.hpp"

namespace spinewatch {

// libpng's png_image, freed (with the file it holds open) however the
// reading ends. Its address must not change while libpng holds it, hence
// the heap.
struct PngFile::Header {
  png_image image{};
  Header() { image.version = PNG_IMAGE_VERSION; }
  ~Header() { png_image_free(&image); }
  Header(const Header&) = delete;
  Header& operator=(const Header&) = delete;
};

namespace {

bool has_png_signature(const std::filesystem::path& path) {
  std::array<png_byte, 8> head{};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(head.data()), head.size());
  return in && png_sig_cmp(head.data(), 0, head.size()) == 0;
}

std::string reason_of(const png_image& image) { return printable(image.message); }

}  // namespace

PngFile::PngFile(std::unique_ptr<Header> header, std::filesystem::path path)
    : header_(std::move(header)), path_(std::move(path)) {}
PngFile::PngFile(PngFile&&) noexcept = default;
PngFile& PngFile::operator=(PngFile&&) noexcept = default;
PngFile::~PngFile() = default;

Result<PngFile> PngFile::open(const std::filesystem::path& path) {
  if (!has_png_signature(path)) return Error{fmt::format("{}: not a PNG file", path.string())};
  auto header = std::make_unique<Header>();
  if (!png_image_begin_read_from_file(&header->image, path.c_str()))
    return Error{fmt::format("{}: cannot be read as a PNG file (libpng: {})", path.string(), reason_of(header->image))};
  return PngFile(std::move(header), path);
}

std::uint32_t PngFile::width() const { return header_->image.width; }
std::uint32_t PngFile::height() const { return header_->image.height; }
bool PngFile::colour() const { return (header_->image.format & PNG_FORMAT_FLAG_COLOR) != 0; }
bool PngFile::deep() const { return (header_->image.format & PNG_FORMAT_FLAG_LINEAR) != 0; }

Result<cv::Mat> PngFile::decode() {
  png_image& image = header_->image;
  if (!image.opaque) return Error{fmt::format("{}: already decoded", path_.string())};
  const bool alpha = (image.format & PNG_FORMAT_FLAG_ALPHA) != 0;
  const int channels = (colour() ? 3 : 1) + (alpha ? 1 : 0);
  // Samples as they are in the file (8-bit sRGB in and out: no conversion),
  // alpha kept and dropped below, not composited.
  image.format = (colour() ? PNG_FORMAT_BGR : PNG_FORMAT_GRAY) | (alpha ? PNG_FORMAT_FLAG_ALPHA : 0u);
  cv::Mat pixels(static_cast<int>(image.height), static_cast<int>(image.width), CV_8UC(channels));
  if (!png_image_finish_read(&image, nullptr, pixels.data, static_cast<png_int_32>(pixels.step[0]), nullptr))
    return Error{fmt::format("{}: cannot be decoded, cut short or damaged (libpng: {})", path_.string(), reason_of(image))};
  if (!alpha) return pixels;
  cv::Mat opaque;
  if (colour())
    cv::cvtColor(pixels, opaque, cv::COLOR_BGRA2BGR);
  else
    cv::extractChannel(pixels, opaque, 0);
  return opaque;
}

namespace {

// libpng reports a write error by calling this, which must not return:
// the message is kept and control goes back to write_png's setjmp.
void on_write_error(png_structp png, png_const_charp message) {
  auto* reason = static_cast<std::string*>(png_get_error_ptr(png));
  if (reason) *reason = printable(message ? message : "unknown error");
  png_longjmp(png, 1);
}
void on_write_warning(png_structp, png_const_charp) {}

struct CloseFile {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

// libpng's full API, not the simplified one: that one always adds an sRGB
// chunk, and a colour-managed reader (libpng's own grey conversion among
// them) then converts to grey in linear light instead of giving the luma.
// The file here carries the samples only.
Status write_png(const std::filesystem::path& path, const cv::Mat& image) {
  if (image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3) || image.empty())
    return Error{fmt::format("{}: only 8-bit grey or colour images are written", path.string())};
  std::unique_ptr<std::FILE, CloseFile> file(std::fopen(path.c_str(), "wb"));
  if (!file) return Error{fmt::format("{}: cannot be written: {}", path.string(), std::strerror(errno))};
  // On the heap: an automatic object changed between setjmp and longjmp
  // would be indeterminate after the jump.
  const auto reason = std::make_unique<std::string>();
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, reason.get(), on_write_error, on_write_warning);
  if (!png) return Error{fmt::format("{}: cannot be written: out of memory", path.string())};
  png_infop info = png_create_info_struct(png);
  // Only trivially destructible objects are made between here and the last
  // libpng call: a longjmp back here skips no destructor.
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return Error{fmt::format("{}: cannot be written: {}", path.string(), reason->empty() ? "out of memory" : *reason)};
  }
  png_init_io(png, file.get());
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows), 8,
               image.channels() == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (image.channels() == 3) png_set_bgr(png);
  for (int y = 0; y < image.rows; ++y) png_write_row(png, image.ptr(y));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(file.get()) != 0 || std::ferror(file.get()))
    return Error{fmt::format("{}: cannot be written: {}", path.string(), std::strerror(errno))};
  return Ok{};
}

}  // namespace spinewatch
