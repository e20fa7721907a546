#pragma once
// A phantom recording: a scenario played by a subject in front of the two
// calibrated cameras, frame by frame, with the true spine for each frame.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "spinewatch/capture/background_images.hpp"
#include "spinewatch/capture/recording.hpp"
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/frames/frame_pair.hpp"
#include "spinewatch/frames/result.hpp"
#include "spinewatch/phantom/body.hpp"
#include "spinewatch/phantom/renderer.hpp"
#include "spinewatch/phantom/room.hpp"
#include "spinewatch/phantom/scenario.hpp"
#include "spinewatch/phantom/station.hpp"
#include "spinewatch/phantom/subject.hpp"

namespace spinewatch::phantom {

inline constexpr int kImageWidth = 320, kImageHeight = 240;

struct PhantomOptions {
  std::string scenario = "upright";
  Subject subject;                 // the generic adult unless a file is given
  std::optional<int> frames;       // person frames; the scenario's default otherwise
  std::uint32_t seed = 1;
  double noise_sigma = 2.0;        // grey levels
  double flicker = 0.03;           // ± relative gain per frame
  bool shadow = false;
  int empty_frames = 10;           // empty scene first, for background learning
  // Scene conditions (docs/phantom.md, "Conditions"):
  // the light falls by this fraction over the recording, twice as much on
  // one side of each view as on the other (a window clouding over);
  double light_drift = 0;
  // a second person walks behind the subject, across the frontal view.
  bool passer_by = false;
  // Colour: the cameras deliver YUYV with chroma (a warm wall, a blue
  // shirt, navy trousers, skin); otherwise U = V = 128.
  bool colour = false;
  // The clothing and skin as bright as the wall behind them: only colour
  // tells the person from the scene.
  bool camouflage = false;
  CameraRig rig = CameraRig::default_rig();
  // Station geometry (station.hpp): when given, the rig is built from it
  // and `rig` above is not used.
  std::optional<StationGeometry> station;
  // Which way the subject faces, degrees counter-clockwise seen from above
  // (180: the back to the frontal camera); the truth turns with the body.
  double heading_deg = 0;
  // The room: plain, cluttered, or a photograph per view (BGR, both or
  // neither; load_backdrop reads one) scaled to cover the view.
  RoomKind room = RoomKind::Plain;
  std::array<cv::Mat, 2> backdrop;  // index: View
  // The furniture in front of the subject (a desk when seated, a bench when
  // standing): on or off; nothing: as the scenario has it.
  std::optional<bool> desk;
  // A chair under a seated subject (room.hpp, chair_boxes): part of the
  // room, in the empty scene too. None by default.
  Chair chair = Chair::None;
  // The frames of a written recording through H.264 at this CRF
  // (compression.hpp); render() itself stays uncompressed.
  std::optional<int> h264_crf;
};

struct PhantomFrame {
  std::uint64_t seq = 0;
  std::int64_t t_ns = 0;
  std::array<cv::Mat, 2> luma;    // what each camera delivers (index: View)
  std::array<cv::Mat, 2> clean;   // the same without noise and flicker
  std::array<cv::Mat, 2> person;  // the person layer: 0 where the scene shows
  std::array<cv::Mat, 2> chroma;  // with colour: (U, V) of each pixel as delivered (CV_8UC2); else empty
  Posture truth;
};

// The frame as both cameras would deliver it to the estimator (GREY).
FramePair grey_pair(const PhantomFrame& frame);
// As the cameras deliver it: YUYV with the chroma when the frame has
// colour, GREY otherwise.
FramePair camera_pair(const PhantomFrame& frame);
// YUYV bytes of one view of the frame (neutral chroma without colour).
std::vector<std::uint8_t> yuyv_bytes(const PhantomFrame& frame, int view);

class PhantomSequence {
 public:
  // Checks the options ("unknown scenario …", out-of-range values).
  static Result<PhantomSequence> create(PhantomOptions options);

  int frame_count() const { return options_.empty_frames + person_frames_; }
  // The furniture standing in front of the subject in this recording.
  Furniture furniture() const;
  int person_frames() const { return person_frames_; }
  const PhantomOptions& options() const { return options_; }
  const Scenario& scenario() const { return *scenario_; }
  const BodyModel& body() const { return body_; }
  const cv::Mat& background(View view) const { return renderers_[static_cast<int>(view)].background(); }
  const cv::Mat& background_chroma(View view) const { return renderers_[static_cast<int>(view)].background_chroma(); }
  const CameraModel& camera(View view) const {
    return view == View::Frontal ? options_.rig.frontal : options_.rig.lateral;
  }

  // Frame `index` (empty frames first); any frame may be rendered alone and
  // is identical to the same frame of a whole recording.
  PhantomFrame render(int index) const;
  Posture ground_truth(int index) const;
  // The subject as it was rendered (posture, joint factors) for recording.json.
  nlohmann::json subject_json() const;
  std::string notes() const;

 private:
  PhantomSequence(PhantomOptions options, const Scenario& scenario, int person_frames);
  RoomSetup room(int view) const;
  std::optional<BodyPose> pose_at(int index) const;  // nothing for an empty frame
  std::optional<BodyPose> passer_at(int index) const;  // nothing when out of the scene
  cv::Mat light(const cv::Mat& clean, int index) const;
  cv::Mat light_chroma(const cv::Mat& chroma, int index) const;
  double light_gain(int x, int width, int index) const;  // light drift at column x of frame `index`

  PhantomOptions options_;
  const Scenario* scenario_;
  int person_frames_;
  BodyModel body_;
  BodyModel passer_;  // drawn only with options().passer_by
  std::array<ViewRenderer, 2> renderers_;
  SensorModel sensor_;
};

// The empty scene as the station would store it (spinewatch background):
// grey, or YUYV with colour; noise-free.
SceneImage stored_background(const PhantomSequence& sequence, View view);

std::int64_t frame_time_ns(std::uint64_t index);  // round(index · 1e9 / 30)

// Writes DIR/frontal.raw, lateral.raw (YUYV), recording.json,
// calibration.yaml, ground_truth.ndjson and background_{frontal,lateral}.png.
Status write_recording(const PhantomSequence& sequence, const std::filesystem::path& dir);

}  // namespace spinewatch::phantom
