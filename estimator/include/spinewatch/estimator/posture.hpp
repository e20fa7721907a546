#pragma once
// The result for one frame pair (docs/interfaces.md §3).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "spinewatch/estimator/anatomy/worker.hpp"
#include "spinewatch/estimator/vertebra_levels.hpp"

namespace spinewatch {

enum class TrackingState : std::uint8_t { Init, Tracking, Lost };
std::string_view to_string(TrackingState state);

struct VertebraPose {
  Eigen::Vector3d body_center = Eigen::Vector3d::Zero();  // mm, world
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // local → world, unit
};
using SpinePose = std::array<VertebraPose, kVertebraCount>;

// Optional fields, each documented in docs/protocol.md.
struct FitDiagnostics {
  double cost = 0.0;  // XOR pixels / silhouette pixels, both views together
  std::optional<std::int64_t> xor_frontal_px, xor_lateral_px;
  std::optional<std::int64_t> silhouette_frontal_px, silhouette_lateral_px;
  std::optional<int> candidates;     // cost evaluations this frame
  std::optional<std::string> flag;   // e.g. "two_blobs", "occluded", "no_person"
};

struct LevelAngles {  // relative rotation of a vertebra to the one below, degrees
  std::string level;  // "T1-T2"
  double flexion = 0, lateral = 0, twist = 0;
};

struct LevelLoad {
  std::string level;  // vertebra name
  double compression_n = 0;
};

struct ErgonomicFlag {
  std::string rule;      // "iso11226_trunk_inclination", "niosh_action_limit", …
  std::string severity;  // "ok" | "conditional" | "not_acceptable"
  double value = 0;      // the measured quantity (deg or N)
  double held_s = 0;     // how long the condition has held
};

struct Ergonomics {
  double trunk_inclination_deg = 0, lateral_bend_deg = 0, twist_deg = 0;
  int reba_trunk = 1;
  std::vector<ErgonomicFlag> flags;
};

// Both views' background counters together (silhouette/background_model.hpp).
struct BackgroundCounts {
  std::uint64_t updates = 0, relearns = 0, bootstraps = 0;
};

struct Posture {
  std::uint64_t seq = 0;
  std::int64_t t_ns = 0;
  TrackingState state = TrackingState::Lost;
  std::optional<Eigen::Vector3d> neck, waist;   // null when lost
  std::optional<SpinePose> vertebrae;           // null when lost
  FitDiagnostics fit;
  std::int64_t latency_us = 0;

  std::optional<Eigen::Vector3d> neck_dir, waist_dir;  // unit, along the spine, pointing up
  std::vector<LevelAngles> angles;
  std::vector<LevelLoad> loads;
  std::optional<Ergonomics> ergonomics;
  BackgroundCounts background;  // the daemon publishes these in "stats"
  // Stature and mass the estimator works with, and where each comes from;
  // nothing until the subject's model holds one (a given stature: at once).
  std::optional<WorkerBody> worker;
};

}  // namespace spinewatch
