#pragma once
// The room around the subject (docs/phantom.md, "Scenes"): the plain wall
// and floor, a cluttered room, or a photograph; and furniture in front of
// the subject, which is part of the room (in the empty scene too) and hides
// whatever of the person is behind it.
#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/frames/result.hpp"
#include "spinewatch/phantom/body.hpp"
#include "spinewatch/phantom/scenario.hpp"

namespace spinewatch::phantom {

enum class RoomKind : std::uint8_t {
  Plain,      // a textured wall 1.5 m behind the subject and the floor (as always)
  Cluttered,  // shelves of books, posters, cabinets and boxes, a tiled floor with a rug
};

// A chair under a seated subject, by its colour: none (the subject sits on
// nothing the cameras see, as always), black (the common office chair:
// darker than the darkest clothing by less than the silhouette's grey
// threshold) or light grey fabric.
enum class Chair : std::uint8_t { None, Black, Grey };

// An opaque box of the room: its centre, axes (columns), half-extents (mm),
// grey level and chroma offsets (U − 128, V − 128).
struct SceneBox {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  float shade = 128;
  cv::Vec2f chroma{0, 0};
  // Distance along the ray to the box (mm), or infinity when it misses.
  double hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;
};

// The furniture in front of a subject facing `heading_deg` (station.hpp's
// turn of the body), as boxes in the world.
std::vector<SceneBox> furniture_boxes(Furniture furniture, double heading_deg);

// A chair under a seated subject: the seat where `place` puts it (50 mm
// thick), four legs to the floor and a backrest behind the buttocks up to
// the lower ribs, turned with the subject. The person sits on it, so it
// hides only what of the person sinks into the seat or lies behind the
// backrest. Nothing for Chair::None.
std::vector<SceneBox> chair_boxes(Chair chair, const ChairPlace& place, double heading_deg);

// What one view's room holds beyond the plain scene.
struct RoomSetup {
  RoomKind kind = RoomKind::Plain;
  cv::Mat backdrop;  // a photograph (CV_8UC3, BGR) standing in for the whole room; empty: none
  std::vector<SceneBox> furniture;
  bool empty() const { return kind == RoomKind::Plain && backdrop.empty() && furniture.empty(); }
};

// Paints the room into one view's noise-free scene (luma CV_32F, chroma
// CV_32FC2 offsets), replacing what the plain scene drew where the room
// differs, and returns the depth (camera z, mm) of the furniture at each
// pixel (infinity where none): what hides the person.
cv::Mat paint_room(const RoomSetup& room, const CameraModel& camera, std::uint32_t seed, int view_index, cv::Mat& luma,
                   cv::Mat& chroma);

}  // namespace spinewatch::phantom
