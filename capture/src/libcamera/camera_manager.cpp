#include "camera_manager.hpp"

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <ostream>
#include <streambuf>
#include <string>

#include <fmt/format.h>
#include <libcamera/camera.h>
#include <libcamera/logging.h>
#include <libcamera/property_ids.h>
#include <libcamera/stream.h>
#include <spdlog/spdlog.h>

#include "spinewatch/capture/libcamera_camera.hpp"

namespace spinewatch {
namespace lc {

namespace {

// libcamera's log lines, into ours: WARN and ERROR (and FATAL) at those
// levels, everything else at debug, so that `spinewatch devices` is not
// buried under pipeline chatter. LIBCAMERA_LOG_FILE still overrides.
class LogForwarder final : public std::streambuf {
 protected:
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    std::lock_guard lock(mutex_);
    pending_.append(s, static_cast<std::size_t>(n));
    for (auto end = pending_.find('\n'); end != std::string::npos; end = pending_.find('\n')) {
      emit(pending_.substr(0, end));
      pending_.erase(0, end + 1);
    }
    return n;
  }
  int_type overflow(int_type c) override {
    if (c == traits_type::eof()) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    xsputn(&ch, 1);
    return c;
  }

 private:
  static void emit(const std::string& line) {
    // Without libcamera's image-processing modules (Debian: libcamera-ipa)
    // it warns at every start; only cameras behind an ISP (a Raspberry Pi's)
    // need them, UVC cameras do not. Said once, in words, not as a warning.
    if (line.find("No IPA found") != std::string::npos) {
      spdlog::debug("libcamera: {}", line);
      static std::once_flag once;
      std::call_once(once, [] {
        spdlog::info("libcamera: no image-processing (IPA) modules installed: fine for USB (UVC) cameras; cameras "
                     "behind an ISP, such as a Raspberry Pi's, need the libcamera-ipa package (docs/hardware.md)");
      });
      return;
    }
    if (line.find(" ERROR ") != std::string::npos || line.find(" FATAL ") != std::string::npos)
      spdlog::error("libcamera: {}", line);
    else if (line.find(" WARN ") != std::string::npos)
      spdlog::warn("libcamera: {}", line);
    else
      spdlog::debug("libcamera: {}", line);
  }
  std::mutex mutex_;
  std::string pending_;
};

void forward_libcamera_log() {
  if (std::getenv("LIBCAMERA_LOG_FILE")) return;
  // Never freed: libcamera may log while the process exits.
  static auto* forwarder = new LogForwarder();
  static auto* stream = new std::ostream(forwarder);
  libcamera::logSetStream(stream, false);
}

}  // namespace

Result<std::shared_ptr<libcamera::CameraManager>> shared_camera_manager() {
  static std::mutex mutex;
  static std::weak_ptr<libcamera::CameraManager> shared;
  std::lock_guard lock(mutex);
  if (auto manager = shared.lock()) return manager;
  forward_libcamera_log();
  auto* raw = new libcamera::CameraManager();
  if (const int err = raw->start(); err < 0) {
    delete raw;
    return Error{fmt::format("libcamera: the camera manager did not start: {}", std::strerror(-err))};
  }
  std::shared_ptr<libcamera::CameraManager> manager(raw, [](libcamera::CameraManager* m) {
    m->stop();
    delete m;
  });
  shared = manager;
  return manager;
}

}  // namespace lc

bool libcamera_built() { return true; }

Result<std::vector<LibcameraCameraInfo>> list_libcamera_cameras() {
  auto manager = lc::shared_camera_manager();
  if (!manager) return manager.error();
  std::vector<LibcameraCameraInfo> out;
  for (const auto& camera : (*manager)->cameras()) {
    LibcameraCameraInfo info;
    info.id = camera->id();
    info.model = camera->properties().get(libcamera::properties::Model).value_or("");
    if (auto config = camera->generateConfiguration({libcamera::StreamRole::Viewfinder}); config && !config->empty()) {
      const auto& formats = config->at(0).formats();
      for (const auto& pf : formats.pixelformats()) {
        const auto range = formats.range(pf);
        info.formats.push_back(fmt::format("{} {}-{}", pf.toString(), range.min.toString(), range.max.toString()));
      }
    }
    out.push_back(std::move(info));
  }
  return out;
}

}  // namespace spinewatch
