#include "spinewatch/phantom/phantom.hpp"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "spinewatch/phantom/compression.hpp"

namespace spinewatch::phantom {
namespace {

SubjectPosture posture_for(const PhantomOptions& options, const Scenario& scenario) {
  return scenario.seated ? SubjectPosture::Seated : options.subject.posture;
}

std::string scenario_names() {
  std::string names;
  for (const Scenario& s : scenarios()) names += (names.empty() ? "" : ", ") + std::string(s.name);
  return names;
}

}  // namespace

std::int64_t frame_time_ns(std::uint64_t index) { return std::llround(double(index) * 1e9 / kPhantomFps); }

Result<PhantomSequence> PhantomSequence::create(PhantomOptions options) {
  const Scenario* scenario = find_scenario(options.scenario);
  if (!scenario) return Error{fmt::format("unknown scenario \"{}\" (known: {})", options.scenario, scenario_names())};
  const int frames = options.frames.value_or(scenario->default_frames);
  if (frames < 1 || frames > 100000) return Error{fmt::format("frames: {} is out of range [1, 100000]", frames)};
  if (options.empty_frames < 0 || options.empty_frames > 10000)
    return Error{fmt::format("empty frames: {} is out of range [0, 10000]", options.empty_frames)};
  if (!(options.noise_sigma >= 0 && options.noise_sigma <= 50))
    return Error{fmt::format("noise: {} is out of range [0, 50]", options.noise_sigma)};
  if (!(options.flicker >= 0 && options.flicker <= 0.5))
    return Error{fmt::format("flicker: {} is out of range [0, 0.5]", options.flicker)};
  if (!(options.light_drift >= 0 && options.light_drift <= 0.6))
    return Error{fmt::format("light drift: {} is out of range [0, 0.6]", options.light_drift)};
  if (!(options.heading_deg >= -360 && options.heading_deg <= 360))
    return Error{fmt::format("heading: {} is out of range [-360, 360]", options.heading_deg)};
  if (options.backdrop[0].empty() != options.backdrop[1].empty())
    return Error{"backdrop: give a photograph for both views (frontal and lateral) or for neither"};
  if (options.h264_crf && (*options.h264_crf < kMinCrf || *options.h264_crf > kMaxCrf))
    return Error{fmt::format("h264: CRF {} is out of range [{}, {}]", *options.h264_crf, kMinCrf, kMaxCrf)};
  if (options.chair != Chair::None && posture_for(options, *scenario) != SubjectPosture::Seated)
    return Error{fmt::format("chair: the subject of \"{}\" stands; a chair needs a seated scenario (typing, "
                             "seated_flexion) or a seated subject",
                             scenario->name)};
  if (options.station) {
    auto rig = station_rig(*options.station);
    if (!rig) return rig.error();
    options.rig = std::move(rig).value();
  }
  return PhantomSequence(std::move(options), *scenario, frames);
}

PhantomSequence::PhantomSequence(PhantomOptions options, const Scenario& scenario, int person_frames)
    : options_(std::move(options)),
      scenario_(&scenario),
      person_frames_(person_frames),
      body_(options_.subject, posture_for(options_, scenario), options_.seed),
      passer_(Subject{}, SubjectPosture::Standing, options_.seed + 1),
      renderers_{ViewRenderer(options_.rig.frontal, {kImageWidth, kImageHeight}, options_.seed, 0, room(0)),
                 ViewRenderer(options_.rig.lateral, {kImageWidth, kImageHeight}, options_.seed, 1, room(1))},
      sensor_(options_.seed, options_.noise_sigma, options_.flicker) {}

Furniture PhantomSequence::furniture() const {
  if (!options_.desk) return scenario_->furniture;
  if (!*options_.desk) return Furniture::None;
  if (scenario_->furniture != Furniture::None) return scenario_->furniture;
  return posture_for(options_, *scenario_) == SubjectPosture::Seated ? Furniture::Desk : Furniture::Bench;
}

RoomSetup PhantomSequence::room(int view) const {
  RoomSetup setup;
  setup.kind = options_.room;
  setup.backdrop = options_.backdrop[std::size_t(view)];
  setup.furniture = furniture_boxes(furniture(), options_.heading_deg);
  if (options_.chair != Chair::None) {
    const std::vector<SceneBox> chair = chair_boxes(options_.chair, body_.chair_place(), options_.heading_deg);
    setup.furniture.insert(setup.furniture.end(), chair.begin(), chair.end());
  }
  return setup;
}

std::optional<BodyPose> PhantomSequence::pose_at(int index) const {
  const int i = index - options_.empty_frames;
  if (i < 0) return std::nullopt;
  const TrunkMotion motion = scenario_->motion(i, person_frames_);
  std::optional<BodyPose> body;
  if (scenario_->limbs) {
    const LimbMotion limbs = scenario_->limbs(i, person_frames_);
    body = body_.pose(motion, &limbs);
  } else {
    body = body_.pose(motion);
  }
  if (options_.heading_deg != 0) turn(*body, options_.heading_deg);
  return body;
}

// The passer-by walks at 1.2 m/s along the wall side of the subject
// (0.7 m behind them), across the frontal view and towards the lateral
// camera, entering a third of the way through the recording.
std::optional<BodyPose> PhantomSequence::passer_at(int index) const {
  if (!options_.passer_by) return std::nullopt;
  constexpr double kBehindMm = 700, kSpeedMmPerFrame = 1200.0 / kPhantomFps, kStartZMm = -1400;
  const int start = frame_count() / 3;
  const double z = kStartZMm + (index - start) * kSpeedMmPerFrame;
  if (index < start || z > -kStartZMm) return std::nullopt;
  TrunkMotion walk;
  walk.sway_mm = Eigen::Vector3d(-kBehindMm, 0, z);
  return passer_.pose(walk);
}

// Light drift: the scene (person included) lit less and less, by
// light_drift on average at the end, from 0.5× that at one side of the
// image to 1.5× at the other.
double PhantomSequence::light_gain(int x, int width, int index) const {
  const double t = frame_count() > 1 ? double(index) / double(frame_count() - 1) : 0.0;
  const double side = 0.5 + double(x) / double(std::max(1, width - 1));
  return 1.0 - options_.light_drift * t * side;
}

cv::Mat PhantomSequence::light(const cv::Mat& clean, int index) const {
  if (options_.light_drift <= 0) return clean;
  cv::Mat out(clean.size(), CV_8U);
  for (int y = 0; y < clean.rows; ++y)
    for (int x = 0; x < clean.cols; ++x)
      out.at<std::uint8_t>(y, x) =
          cv::saturate_cast<std::uint8_t>(light_gain(x, clean.cols, index) * clean.at<std::uint8_t>(y, x));
  return out;
}

// The same light on the chroma offsets: light scales them as it scales luma.
cv::Mat PhantomSequence::light_chroma(const cv::Mat& chroma, int index) const {
  if (options_.light_drift <= 0) return chroma;
  cv::Mat out = chroma.clone();
  for (int y = 0; y < out.rows; ++y)
    for (int x = 0; x < out.cols; ++x) out.at<cv::Vec2f>(y, x) *= float(light_gain(x, out.cols, index));
  return out;
}

PhantomFrame PhantomSequence::render(int index) const {
  PhantomFrame frame;
  frame.seq = std::uint64_t(index);
  frame.t_ns = frame_time_ns(frame.seq);
  const std::optional<BodyPose> body = pose_at(index);
  const std::optional<BodyPose> passer = passer_at(index);
  for (int view = 0; view < 2; ++view) {
    const ViewRenderer& renderer = renderers_[std::size_t(view)];
    const auto v = std::size_t(view);
    frame.person[v] = body ? renderer.person_layer(*body) : cv::Mat::zeros(renderer.background().size(), CV_8U);
    cv::Mat scene_layer = frame.person[v];
    if (passer) {
      // Both people in one painter's pass; the person layer (the truth of
      // what the subject covers) stays the subject's alone.
      BodyPose both = *passer;
      if (body) both.solids.insert(both.solids.end(), body->solids.begin(), body->solids.end());
      scene_layer = renderer.person_layer(both);
    }
    const bool anyone = body || passer;
    frame.clean[v] = anyone ? renderer.compose(scene_layer, options_.shadow, options_.camouflage)
                            : renderer.background().clone();
    frame.clean[v] = light(frame.clean[v], index);
    frame.luma[v] = sensor_.expose(frame.clean[v], frame.seq, view);
    if (options_.colour) {
      cv::Mat chroma = anyone ? renderer.compose_chroma(scene_layer, options_.shadow) : renderer.background_chroma().clone();
      frame.chroma[v] = sensor_.expose_chroma(light_chroma(chroma, index), frame.seq, view);
    }
  }
  frame.truth = ground_truth(index);
  return frame;
}

Posture PhantomSequence::ground_truth(int index) const {
  Posture p;
  p.seq = std::uint64_t(index);
  p.t_ns = frame_time_ns(p.seq);
  p.fit.cost = 0;
  p.latency_us = 0;
  const std::optional<BodyPose> body = pose_at(index);
  if (!body) {
    p.state = TrackingState::Lost;
    return p;
  }
  p.state = TrackingState::Tracking;
  p.vertebrae = body->spine;
  p.neck = body->spine[kNeckIndex].body_center;
  p.waist = body->spine[kWaistIndex].body_center;
  p.neck_dir = body->spine[kNeckIndex].q * Eigen::Vector3d::UnitY();
  p.waist_dir = body->spine[kWaistIndex].q * Eigen::Vector3d::UnitY();
  const auto angles = intervertebral_angles(body->spine);
  const SpineSpec& spec = generic_spine_spec();
  for (std::size_t i = 0; i < kJointCount; ++i)
    p.angles.push_back({spec.joints[i].name, angles[i].flexion, angles[i].lateral, angles[i].twist});
  return p;
}

nlohmann::json PhantomSequence::subject_json() const {
  Subject rendered = body_.subject();
  rendered.posture = body_.posture();
  rendered.joint_factors = body_.joint_factors();
  return to_json(rendered);
}

std::string PhantomSequence::notes() const {
  std::string notes = fmt::format(
      "phantom scenario={} seed={} frames={} empty_frames={} noise={} flicker={} shadow={} light_drift={} passer_by={} "
      "colour={} camouflage={}",
      scenario_->name, options_.seed, person_frames_, options_.empty_frames, options_.noise_sigma, options_.flicker,
      options_.shadow, options_.light_drift, options_.passer_by, options_.colour, options_.camouflage);
  // The newer options only when given: older recordings' notes stay as they were.
  if (const auto& g = options_.station)
    notes += fmt::format(" camera_tilt={} camera_roll={} pair_angle={} camera_height={}",
                         g->tilt_deg ? fmt::format("{}", *g->tilt_deg) : "auto", g->roll_deg, g->pair_angle_deg,
                         g->height_mm ? fmt::format("{}", *g->height_mm) : "auto");
  if (options_.heading_deg != 0) notes += fmt::format(" heading={}", options_.heading_deg);
  if (options_.room == RoomKind::Cluttered) notes += " room=cluttered";
  if (!options_.backdrop[0].empty()) notes += " backdrop=photographs";
  if (furniture() != Furniture::None) notes += furniture() == Furniture::Desk ? " furniture=desk" : " furniture=bench";
  if (options_.chair != Chair::None) notes += options_.chair == Chair::Black ? " chair=black" : " chair=grey";
  if (options_.h264_crf) notes += fmt::format(" h264_crf={}", *options_.h264_crf);
  return notes;
}

FramePair grey_pair(const PhantomFrame& f) {
  auto bytes = [](const cv::Mat& m) { return std::vector<std::uint8_t>(m.datastart, m.dataend); };
  const FrameFormat format = FrameFormat::packed(PixelFormat::GREY, static_cast<std::uint32_t>(f.luma[0].cols),
                                                 static_cast<std::uint32_t>(f.luma[0].rows));
  return FramePair{f.seq, f.t_ns, Frame::owning(format, {f.seq, f.t_ns}, bytes(f.luma[0])),
                   Frame::owning(format, {f.seq, f.t_ns}, bytes(f.luma[1]))};
}

SceneImage stored_background(const PhantomSequence& sequence, View view) {
  const cv::Mat& luma = sequence.background(view);
  SceneImage image{luma.cols, luma.rows, 1, {}};
  if (sequence.options().colour) {
    cv::Mat chroma;
    sequence.background_chroma(view).convertTo(chroma, CV_8UC2, 1.0, 128.0);
    image.step = 2;
    image.pixels = to_yuyv(luma, chroma);
  } else {
    image.pixels.assign(luma.datastart, luma.dataend);
  }
  return image;
}

std::vector<std::uint8_t> yuyv_bytes(const PhantomFrame& f, int view) {
  const auto v = std::size_t(view);
  return f.chroma[v].empty() ? to_yuyv(f.luma[v]) : to_yuyv(f.luma[v], f.chroma[v]);
}

FramePair camera_pair(const PhantomFrame& f) {
  if (f.chroma[0].empty()) return grey_pair(f);
  const FrameFormat format = FrameFormat::packed(PixelFormat::YUYV, static_cast<std::uint32_t>(f.luma[0].cols),
                                                 static_cast<std::uint32_t>(f.luma[0].rows));
  return FramePair{f.seq, f.t_ns, Frame::owning(format, {f.seq, f.t_ns}, yuyv_bytes(f, 0)),
                   Frame::owning(format, {f.seq, f.t_ns}, yuyv_bytes(f, 1))};
}

}  // namespace spinewatch::phantom
