#include "spinewatch/overlay/overlay.hpp"

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch {
namespace {

namespace colour = overlay_colour;

// Sub-pixel drawing: OpenCV takes fixed-point coordinates with this many fraction bits.
constexpr int kShift = 4;
constexpr double kOne = 1 << kShift;

const CameraModel& camera_of(const CameraRig& rig, int view) { return view == 0 ? rig.frontal : rig.lateral; }

// A camera pixel (u, v) covers the block [u·s, u·s + s) of the overlay; its
// centre u is drawn at the block's centre.
std::optional<cv::Point2d> view_point(const CameraModel& camera, const Eigen::Vector3d& world, int scale) {
  const auto p = camera.project(world);
  if (!p) return std::nullopt;
  const double half = (scale - 1) * 0.5;
  return cv::Point2d(p->x() * scale + half, p->y() * scale + half);
}

cv::Point fixed(const cv::Point2d& p) {
  return {static_cast<int>(std::lround(p.x * kOne)), static_cast<int>(std::lround(p.y * kOne))};
}

cv::Mat upscale(const cv::Mat& image, int scale) {
  if (scale == 1) return image;
  cv::Mat big;
  cv::resize(image, big, cv::Size(), scale, scale, cv::INTER_NEAREST);
  return big;
}

cv::Mat frame_to_bgr(const Frame& frame, int width, int height, int scale) {
  cv::Mat grey(height, width, CV_8UC1, cv::Scalar(0));
  if (!frame.empty()) {
    const LumaView luma = frame.luma();
    for (int y = 0; y < std::min(height, luma.height); ++y) {
      auto* row = grey.ptr<std::uint8_t>(y);
      for (int x = 0; x < std::min(width, luma.width); ++x) row[x] = luma.at(x, y);
    }
  }
  cv::Mat bgr;
  cv::cvtColor(upscale(grey, scale), bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}

cv::Mat mask_image(const BitMask& mask) {
  cv::Mat m(mask.height(), mask.width(), CV_8UC1);
  for (int y = 0; y < mask.height(); ++y) {
    auto* row = m.ptr<std::uint8_t>(y);
    for (int x = 0; x < mask.width(); ++x) row[x] = mask.get(x, y) ? 255 : 0;
  }
  return m;
}

bool fits(const BitMask* mask, const cv::Mat& view, int scale) {
  return mask && !mask->empty() && mask->width() * scale == view.cols && mask->height() * scale <= view.rows;
}

// Privacy (the live view's default): no camera pixels, only where the
// silhouette is, flat over a plain background.
void draw_plain(cv::Mat& view, const BitMask* mask, int scale) {
  view.setTo(colour::kPlainBackground);
  if (!fits(mask, view, scale)) return;
  cv::Mat fill = upscale(mask_image(*mask), scale);
  view(cv::Rect(0, 0, fill.cols, fill.rows)).setTo(colour::kSilhouetteFill, fill);
}

// The contours of the upscaled mask: the outline runs along the boundary
// pixels of the silhouette itself.
void draw_outline(cv::Mat& view, const BitMask* mask, int scale) {
  if (!fits(mask, view, scale)) return;
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(upscale(mask_image(*mask), scale), contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
  cv::drawContours(view, contours, -1, colour::kOutline, 1);
}

void line(cv::Mat& view, const std::optional<cv::Point2d>& a, const std::optional<cv::Point2d>& b,
          const cv::Scalar& c, int thickness = 1) {
  if (a && b) cv::line(view, fixed(*a), fixed(*b), c, thickness, cv::LINE_AA, kShift);
}

// Connected spheres touch their neighbours: a sphere's radius is half the
// mean distance to the adjacent sphere centres.
double sphere_radius(const SpinePose& spine, std::size_t i) {
  double sum = 0;
  int n = 0;
  if (i > 0) sum += (spine[i].body_center - spine[i - 1].body_center).norm(), ++n;
  if (i + 1 < spine.size()) sum += (spine[i].body_center - spine[i + 1].body_center).norm(), ++n;
  return n > 0 ? 0.5 * sum / n : 0.0;
}

void draw_cvsm_surface(cv::Mat& view, const CameraModel& camera, const CvsmResult& fit, const BodyModel& model,
                       int scale) {
  std::vector<Eigen::Vector3d> points;
  control_points(model, fit.vertebrae, points, fit.pose.limbs, fit.pose.heading);
  std::vector<std::optional<cv::Point2d>> px(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) px[i] = view_point(camera, points[i], scale);
  const auto at = [&](int plane, int k) { return px[static_cast<std::size_t>(plane * kControlPoints + k)]; };
  // The surface is context, not the subject: drawn half transparent so the
  // frame and the silhouette stay readable under it.
  cv::Mat surface = view.clone();
  for (std::size_t p = 0; p < model.planes.size(); ++p)
    for (int k = 0; k < kControlPoints; ++k)
      line(surface, at(static_cast<int>(p), k), at(static_cast<int>(p), (k + 1) % kControlPoints), colour::kSurface);
  // The solid between adjacent planes, shown by its front, back and side edges.
  for (const auto& chain : model.chains)
    for (std::size_t j = 0; j + 1 < chain.size(); ++j)
      for (int k = 0; k < kControlPoints; k += kControlPoints / 4)
        line(surface, at(chain[j], k), at(chain[j + 1], k), colour::kSurface);
  cv::addWeighted(surface, 0.55, view, 0.45, 0.0, view);
}

void draw_cvsm_spheres(cv::Mat& view, const CameraModel& camera, const CvsmResult& fit, int scale) {
  const double fx = camera.camera_matrix(0, 0);
  for (std::size_t i = 0; i < fit.vertebrae.size(); ++i) {
    const Eigen::Vector3d& c = fit.vertebrae[i].body_center;
    const auto centre = view_point(camera, c, scale);
    const double depth = camera.to_camera(c).z();
    if (!centre || depth <= 0) continue;
    const double radius_px = sphere_radius(fit.vertebrae, i) * fx / depth * scale;
    cv::circle(view, fixed(*centre), static_cast<int>(std::lround(radius_px * kOne)), colour::kSphere, 1, cv::LINE_AA,
               kShift);
  }
  for (const Eigen::Vector3d* end : {&fit.neck, &fit.waist})
    if (const auto p = view_point(camera, *end, scale))
      cv::drawMarker(view, cv::Point(static_cast<int>(std::lround(p->x)), static_cast<int>(std::lround(p->y))),
                     colour::kEndMarker, cv::MARKER_TILTED_CROSS, 7 * scale, 1);
}

void draw_vertebrae(cv::Mat& view, const CameraModel& camera, const SpinePose& spine, const OverlayOptions& o) {
  for (const VertebraPose& v : spine) {
    const auto centre = view_point(camera, v.body_center, o.scale);
    for (int k = 0; k < 3; ++k)
      line(view, centre, view_point(camera, v.body_center + v.q * (o.axis_mm * Eigen::Vector3d::Unit(k)), o.scale),
           colour::kAxis[k]);
  }
  for (const VertebraPose& v : spine)
    if (const auto centre = view_point(camera, v.body_center, o.scale))
      cv::circle(view, fixed(*centre), static_cast<int>((0.5 * o.scale + 1.0) * kOne), colour::kVertebra, cv::FILLED,
                 cv::LINE_8, kShift);
}

// Text with a dark rim, readable over any grey level.
void text(cv::Mat& image, const std::string& s, cv::Point at, double size, const cv::Scalar& c) {
  cv::putText(image, s, at, cv::FONT_HERSHEY_SIMPLEX, size, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(image, s, at, cv::FONT_HERSHEY_SIMPLEX, size, c, 1, cv::LINE_AA);
}

std::string strip_text(const Posture& p) {
  std::string s = fmt::format("seq {}   {}   cost {:.3f}   latency {} us", p.seq, to_string(p.state), p.fit.cost,
                              p.latency_us);
  if (p.fit.flag) s += "   " + *p.fit.flag;
  return s;
}

}  // namespace

std::optional<cv::Point2d> overlay_point(const CameraRig& rig, int view, const Eigen::Vector3d& world, int width,
                                         const OverlayOptions& options) {
  auto p = view_point(camera_of(rig, view), world, options.scale);
  if (p) p->x += view * width * options.scale;
  return p;
}

cv::Mat render_overlay(const OverlayScene& in, const OverlayOptions& o) {
  static const Posture kNoPosture{};
  const Posture& posture = in.posture ? *in.posture : kNoPosture;
  const int width = in.width, height = in.height, s = o.scale;
  cv::Mat canvas(height * s + o.strip_height * s, 2 * width * s, CV_8UC3, cv::Scalar(0, 0, 0));
  const bool lost = posture.state == TrackingState::Lost;
  // The CVSM is drawn once a subject model exists and this pair was fitted
  // (not while the background is still being learnt).
  const bool fitted = in.rig && !lost && in.fit && in.body_model && in.fit->state != TrackingState::Lost;
  for (int v = 0; v < 2; ++v) {
    cv::Mat view = canvas(cv::Rect(v * width * s, 0, width * s, height * s));
    if (in.frames[v])
      frame_to_bgr(*in.frames[v], width, height, s).copyTo(view);
    else
      draw_plain(view, in.silhouette[v], s);
    if (fitted) draw_cvsm_surface(view, camera_of(*in.rig, v), *in.fit, *in.body_model, s);
    draw_outline(view, in.silhouette[v], s);
    if (fitted) draw_cvsm_spheres(view, camera_of(*in.rig, v), *in.fit, s);
    if (in.rig && !lost && posture.vertebrae) draw_vertebrae(view, camera_of(*in.rig, v), *posture.vertebrae, o);
    text(view, v == 0 ? "frontal" : "lateral", cv::Point(4 * s, 10 * s), 0.35 * s, colour::kText);
    if (lost) text(view, "LOST", cv::Point(width * s / 2 - 22 * s, 28 * s), 0.7 * s, colour::kLost);
  }
  std::string strip = strip_text(posture);
  if (!in.note.empty()) strip += "   " + in.note;
  text(canvas, strip, cv::Point(4 * s, height * s + (o.strip_height - 4) * s), 0.35 * s, colour::kText);
  return canvas;
}

}  // namespace spinewatch
