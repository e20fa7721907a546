#pragma once
// Exposure over a time window (docs/exposure.md): how long, how often and
// how hard the back was loaded, and how much of the window each figure is
// based on. Every duration is in seconds of the stream's clock.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "spinewatch/estimator/load/ergonomics.hpp"

namespace spinewatch {

// ISO 11226 trunk-inclination zones, in the order they are reported.
enum class InclinationZone : std::uint8_t { Extension, Upright, Flexed, Stooped };
inline constexpr std::size_t kInclinationZoneCount = 4;
// extension: below −extension_margin_deg (the estimator's resolution, as
// the per-frame flag has it); upright: up to inclination_ok_deg (20°);
// flexed: up to inclination_max_deg (60°); stooped: beyond.
InclinationZone inclination_zone(double inclination_deg, const ErgonomicLimits& limits);
std::string_view zone_key(InclinationZone zone);  // "extension", "0_20", "20_60", "over_60"

// RULA's trunk score, 1…6 (McAtamney & Corlett 1993): 1 upright (within
// reba_upright_deg, the estimator's resolution), 2 up to 20°, 3 up to 60°,
// 4 beyond, +1 twisted, +1 side-bent (each beyond reba_twist_side_deg).
// Extension scores as upright-to-20°: RULA's trunk diagram has no
// extension band.
int rula_trunk_score(const TrunkAngles& a, const ErgonomicLimits& limits);

enum class SummaryScope : std::uint8_t { Interval, Shift };
std::string_view to_string(SummaryScope scope);

// Lateral bend or axial twist beyond bend_twist_deg (ISO 11226: 10°).
struct BeyondLimit {
  double over_s = 0;         // tracked time beyond the limit
  std::uint32_t entries = 0;  // times it went beyond (from within the limit)
  // entries per minute of tracked time (0 when nothing was tracked)
  double per_minute(double tracked_s) const { return tracked_s > 0 ? entries * 60.0 / tracked_s : 0.0; }
};

struct ExposureSummary {
  SummaryScope scope = SummaryScope::Interval;
  std::int64_t start_ns = 0, end_ns = 0;  // [start, end) on the stream's clock
  bool partial = false;                   // cut short (the stream ended); end_ns is the last time covered

  // Coverage: tracked + init + lost + empty + gap = end − start.
  double tracked_s = 0;  // a posture with trunk angles
  double init_s = 0;     // building the subject's model, or no posture figures yet
  double lost_s = 0;     // someone in view, no posture the station stands behind
  double empty_s = 0;    // nobody in view (fit.flag "no_person")
  double gap_s = 0;      // no pair at all (dropped, or the stream paused beyond max_gap)

  std::array<double, kInclinationZoneCount> zone_s{};  // tracked time per InclinationZone
  double inclination_mean_deg = 0, inclination_min_deg = 0, inclination_max_deg = 0;  // over tracked time

  double bend_twist_limit_deg = 0;  // the limit both are counted against
  BeyondLimit lateral_bend, axial_twist;
  // Tracked time whose axial twist the fit could not resolve (fit.flag
  // "twist_unresolved": its sign unknown). Its magnitude is what over_s and
  // entries counted, as for the rest; this says how much of axial_twist
  // rests on it (docs/exposure.md, "Known limits").
  double twist_unresolved_s = 0;

  // Holds in the 20–60° zone longer than inclination_max_hold_s.
  double hold_limit_s = 0;
  double hold_beyond_s = 0;         // time spent past the limit within such holds
  std::uint32_t holds_beyond = 0;   // holds that passed the limit in this window
  double longest_hold_s = 0;        // the longest 20–60° hold ending or running in this window (its full length)

  std::array<double, 5> reba_trunk_s{};  // tracked time with REBA trunk score 1…5
  std::array<double, 6> rula_trunk_s{};  // tracked time with RULA trunk score 1…6

  // Compression at the lowest lumbar level (L5), from tracked postures with loads.
  double compression_based_on_s = 0;
  double compression_peak_n = 0, compression_mean_n = 0;
  double action_limit_n = 0;          // NIOSH action limit it was compared with
  double above_action_limit_s = 0;
  double cumulative_n_s = 0;          // ∫ compression dt, N·s

  double duration_s() const { return double(end_ns - start_ns) * 1e-9; }
};

}  // namespace spinewatch
