#pragma once
// Both views of a pair side by side (frontal | lateral), each upscaled by an
// integer factor with nearest-neighbour so every camera pixel stays a
// visible block, with what the estimator saw and fitted drawn over it
// (docs/spine-model.md, "What the overlay shows"):
//   silhouette outline        yellow
//   CVSM spheres              magenta circles at their projected radius
//   CVSM body surface         purple, half transparent (control-point rings and links)
//   CVSM neck / waist         cyan tilted crosses
//   vertebra T1…L5 centres    orange dots
//   vertebra local axes       X (anterior) red, Y (superior) green, Z (right) blue
// and a text strip with seq, state, fit cost and latency. Lost pairs get
// the outline and "LOST".
// Under all of it: the camera's own pixels (grey) where the scene gives
// frames, else a plain background with the silhouette filled in flat grey
// (the live view's default: no picture of the worker, docs/security.md).
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/frames/frame.hpp"

namespace spinewatch {

class BitMask;
struct BodyModel;
struct CvsmResult;

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
inline const cv::Scalar kPlainBackground{48, 48, 48};  // no camera pixels
inline const cv::Scalar kSilhouetteFill{110, 110, 110};
}  // namespace overlay_colour

struct OverlayOptions {
  int scale = 2;             // 1: native width × height per view
  double axis_mm = 35.0;     // drawn length of each vertebra axis
  int strip_height = 14;     // text strip below the views, in camera pixels (× scale)
};

// What one overlay shows; pointers may be null (nothing of that is drawn).
struct OverlayScene {
  const CameraRig* rig = nullptr;
  int width = 0, height = 0;                        // one view, camera pixels
  const Frame* frames[2] = {nullptr, nullptr};      // camera pixels; null: the plain background
  const BitMask* silhouette[2] = {nullptr, nullptr};
  const CvsmResult* fit = nullptr;
  const BodyModel* body_model = nullptr;
  const Posture* posture = nullptr;
  std::string note;  // appended to the text strip (e.g. the station's name)
};

// Where a world point lands in the overlay image of a view (0 frontal,
// 1 lateral), for a frame `width` pixels wide: the centre of the camera
// pixel's block. Nothing when the point is behind the camera.
std::optional<cv::Point2d> overlay_point(const CameraRig& rig, int view, const Eigen::Vector3d& world, int width,
                                         const OverlayOptions& options = {});

// The overlay, a BGR image (2·width·scale) × (height + strip)·scale.
cv::Mat render_overlay(const OverlayScene& scene, const OverlayOptions& options = {});

}  // namespace spinewatch
