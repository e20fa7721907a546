#pragma once
// Replay overlays: both views of a pair side by side (frontal | lateral),
// each upscaled by an integer factor with nearest-neighbour so every camera
// pixel stays a visible block, with what the estimator saw and fitted drawn
// over it (docs/spine-model.md, "What the overlay shows"):
//   silhouette outline        yellow
//   CVSM spheres              magenta circles at their projected radius
//   CVSM body surface         purple, half transparent (control-point rings and links)
//   CVSM neck / waist         cyan tilted crosses
//   vertebra T1…L5 centres    orange dots
//   vertebra local axes       X (anterior) red, Y (superior) green, Z (right) blue
// and a text strip with seq, state, fit cost and latency. Lost pairs get
// the frame, the outline and "LOST".
#include <cstdint>
#include <filesystem>
#include <optional>

#include <opencv2/core.hpp>

#include "spinewatch/frames/result.hpp"
#include "spinewatch/replay/replay.hpp"

namespace spinewatch {

// BGR colours of the overlay, public so that tests and docs agree with it.
namespace overlay_colour {
inline const cv::Scalar kOutline{0, 255, 255};
inline const cv::Scalar kSphere{255, 0, 255};
inline const cv::Scalar kSurface{150, 0, 150};
inline const cv::Scalar kEndMarker{255, 255, 0};
inline const cv::Scalar kVertebra{0, 140, 255};
inline const cv::Scalar kAxis[3] = {{0, 0, 255}, {0, 255, 0}, {255, 0, 0}};
inline const cv::Scalar kText{255, 255, 255};
inline const cv::Scalar kLost{0, 0, 255};
}  // namespace overlay_colour

struct OverlayOptions {
  int scale = 2;             // 1: native 320×240 per view
  double axis_mm = 35.0;     // drawn length of each vertebra axis
  int strip_height = 14;     // text strip below the views, in camera pixels (× scale)
};

// Where a world point lands in the overlay image of a view (0 frontal,
// 1 lateral), for a frame `width` pixels wide: the centre of the camera
// pixel's block. Nothing when the point is behind the camera.
std::optional<cv::Point2d> overlay_point(const CameraRig& rig, int view, const Eigen::Vector3d& world, int width,
                                         const OverlayOptions& options = {});

// The overlay of one pair, a BGR image (2·width·scale) × (height + strip)·scale.
cv::Mat render_overlay(const ReplayedPair& pair, const OverlayOptions& options = {});

// Writes the overlay of every `every`-th pair (the first, then every N-th
// after it) as DIR/pair_<seq, 6 digits>.png.
class OverlayWriter {
 public:
  // Creates DIR; an error names DIR when it cannot be created or written.
  static Result<OverlayWriter> create(const std::filesystem::path& dir, std::uint64_t every,
                                      OverlayOptions options = {});

  Status write(const ReplayedPair& pair);
  std::uint64_t written() const { return written_; }

 private:
  OverlayWriter(std::filesystem::path dir, std::uint64_t every, OverlayOptions options)
      : dir_(std::move(dir)), every_(every), options_(options) {}
  std::filesystem::path dir_;
  std::uint64_t every_ = 1;
  OverlayOptions options_;
  std::uint64_t seen_ = 0, written_ = 0;
};

}  // namespace spinewatch
