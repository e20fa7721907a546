#include "spinewatch/phantom/phantom.hpp"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

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
  return PhantomSequence(std::move(options), *scenario, frames);
}

PhantomSequence::PhantomSequence(PhantomOptions options, const Scenario& scenario, int person_frames)
    : options_(std::move(options)),
      scenario_(&scenario),
      person_frames_(person_frames),
      body_(options_.subject, posture_for(options_, scenario), options_.seed),
      renderers_{ViewRenderer(options_.rig.frontal, {kImageWidth, kImageHeight}, options_.seed, 0),
                 ViewRenderer(options_.rig.lateral, {kImageWidth, kImageHeight}, options_.seed, 1)},
      sensor_(options_.seed, options_.noise_sigma, options_.flicker) {}

std::optional<BodyPose> PhantomSequence::pose_at(int index) const {
  const int i = index - options_.empty_frames;
  if (i < 0) return std::nullopt;
  return body_.pose(scenario_->motion(i, person_frames_));
}

PhantomFrame PhantomSequence::render(int index) const {
  PhantomFrame frame;
  frame.seq = std::uint64_t(index);
  frame.t_ns = frame_time_ns(frame.seq);
  const std::optional<BodyPose> body = pose_at(index);
  for (int view = 0; view < 2; ++view) {
    const ViewRenderer& renderer = renderers_[std::size_t(view)];
    if (body) {
      frame.person[std::size_t(view)] = renderer.person_layer(*body);
      frame.clean[std::size_t(view)] = renderer.compose(frame.person[std::size_t(view)], options_.shadow);
    } else {
      frame.person[std::size_t(view)] = cv::Mat::zeros(renderer.background().size(), CV_8U);
      frame.clean[std::size_t(view)] = renderer.background().clone();
    }
    frame.luma[std::size_t(view)] = sensor_.expose(frame.clean[std::size_t(view)], frame.seq, view);
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
  return fmt::format("phantom scenario={} seed={} frames={} empty_frames={} noise={} flicker={} shadow={}", scenario_->name,
                     options_.seed, person_frames_, options_.empty_frames, options_.noise_sigma, options_.flicker,
                     options_.shadow);
}

}  // namespace spinewatch::phantom
