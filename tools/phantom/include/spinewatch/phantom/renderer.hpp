#pragma once
// Images of the phantom: the empty scene and the person as one calibrated
// camera sees them (noise-free), and the sensor that adds noise and flicker.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/phantom/body.hpp"
#include "spinewatch/phantom/room.hpp"

namespace spinewatch::phantom {

class ViewRenderer {
 public:
  // `seed` and `view_index` pick the scene's texture; `room` what the
  // room holds beyond the plain wall and floor (room.hpp).
  ViewRenderer(const CameraModel& camera, cv::Size size, std::uint32_t seed, int view_index, const RoomSetup& room = {});

  // The noise-free empty scene (CV_8U): a wall with a gradient and fixed
  // texture, the floor in front of it.
  const cv::Mat& background() const { return background_; }
  // The person alone (CV_8U): the shade of the nearest body part where the
  // body covers a pixel, 0 elsewhere — and where the room's furniture is
  // nearer the camera than the part.
  cv::Mat person_layer(const BodyPose& body) const;
  // The noise-free scene with the person in it. `camouflage`: the
  // clothing and skin as bright as the wall behind them (only their colour
  // tells them apart).
  // One renderer composes one frame at a time: it keeps its scene-sized
  // working images between calls, and a copy shares them (cv::Mat), so
  // neither a renderer nor its copies may compose on two threads at once.
  cv::Mat compose(const cv::Mat& person_layer, bool shadow, bool camouflage = false) const;

  // Colour, as chroma offsets from neutral (CV_32FC2: U − 128, V − 128):
  // the empty scene (a warm wall, a greyer floor) and the scene with the
  // person, matching compose(): a shadow dims the chroma as it dims the
  // luma, so it keeps the wall's colour.
  const cv::Mat& background_chroma() const { return background_chroma_; }
  cv::Mat compose_chroma(const cv::Mat& person_layer, bool shadow) const;

 private:
  cv::Mat shadow_factor(const cv::Mat& mask) const;  // CV_32F, 1 where no shadow falls

  CameraModel camera_;
  cv::Mat background_;     // CV_8U
  cv::Mat furniture_depth_;  // CV_32F, camera z of the furniture (infinity: none); empty without furniture
  cv::Rect furniture_box_;   // the pixels the furniture covers, bounding box
  cv::Mat background_chroma_;  // CV_32FC2
  cv::Mat cloth_texture_;  // CV_32F, a few grey levels either way
  // compose()'s float working images, kept from frame to frame: allocated
  // afresh they cost a page fault per 4 KB on every frame, a fifth of a
  // long phantom run under the sanitizers (docs/performance.md).
  struct Scratch {
    cv::Mat background, shade, weight, blurred, person;
    cv::Mat reach;  // CV_8U: within the lens blur's reach of the person
    cv::Mat part_depth;  // CV_32F over furniture_box_: the depth of the part drawn at each pixel
  };
  mutable Scratch scratch_;
};

// Exposure flicker (one gain per frame and view) and Gaussian noise,
// deterministic for (seed, frame, view).
class SensorModel {
 public:
  SensorModel(std::uint32_t seed, double noise_sigma, double flicker);
  cv::Mat expose(const cv::Mat& clean, std::uint64_t frame, int view_index) const;
  // The chroma offsets (CV_32FC2) as the same exposure delivers them: the
  // frame's gain, half the luma's noise; CV_8UC2 (U, V).
  cv::Mat expose_chroma(const cv::Mat& chroma, std::uint64_t frame, int view_index) const;

 private:
  std::uint32_t seed_;
  double noise_sigma_, flicker_;
  std::vector<float> gaussian_;  // standard normal samples drawn once
};

// YUYV bytes (Y from the grey image, U = V = 128), packed rows.
std::vector<std::uint8_t> to_yuyv(const cv::Mat& grey);
// YUYV bytes from luma and per-pixel chroma (CV_8UC2), U and V averaged
// over each pixel pair as a 4:2:2 camera does.
std::vector<std::uint8_t> to_yuyv(const cv::Mat& grey, const cv::Mat& chroma);

}  // namespace spinewatch::phantom
