#include <fstream>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>  // the flags; the codecs are the media module's

#include "spinewatch/media/media_files.hpp"
#include "spinewatch/replay/overlay.hpp"

namespace spinewatch {

cv::Mat render_overlay(const ReplayedPair& in, const OverlayOptions& options) {
  const FrameFormat& format = in.pair.frontal.format();
  OverlayScene scene;
  scene.rig = &in.rig;
  scene.width = static_cast<int>(format.width);
  scene.height = static_cast<int>(format.height);
  scene.frames[0] = &in.pair.frontal;
  scene.frames[1] = &in.pair.lateral;
  scene.silhouette[0] = in.trace.silhouette[0];
  scene.silhouette[1] = in.trace.silhouette[1];
  scene.fit = in.trace.fit;
  scene.body_model = in.trace.body_model;
  scene.posture = &in.posture;
  return render_overlay(scene, options);
}

Result<OverlayWriter> OverlayWriter::create(const std::filesystem::path& dir, std::uint64_t every,
                                            OverlayOptions options) {
  if (every == 0) return Error{"overlay: --every must be at least 1"};
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    return Error{fmt::format("{}: cannot create the overlay directory ({})", dir.string(),
                             ec ? ec.message() : "not a directory")};
  // Probe now rather than after a whole replay.
  const auto probe = dir / ".spinewatch-overlay-probe";
  if (!std::ofstream(probe)) return Error{fmt::format("{}: the overlay directory is not writable", dir.string())};
  std::filesystem::remove(probe, ec);
  return OverlayWriter(dir, every, options);
}

Status OverlayWriter::write(const ReplayedPair& pair) {
  if (seen_++ % every_ != 0) return Ok{};
  const auto path = dir_ / fmt::format("pair_{:06d}.png", pair.posture.seq);
  Result<bool> ok = false;
  // zlib level 3: ~10 % larger files than level 9 at a tenth of the time
  // (25 ms against 250 ms a pair here), so --every 1 stays usable.
  try {
    ok = media::write_image(path, render_overlay(pair, options_), {cv::IMWRITE_PNG_COMPRESSION, 3});
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{}: cannot be written ({})", path.string(), e.what())};
  }
  if (!ok) return ok.error();
  if (!*ok) return Error{fmt::format("{}: cannot be written", path.string())};
  ++written_;
  return Ok{};
}

}  // namespace spinewatch
