#include "spinewatch/estimator/load/exposure_accumulator.hpp"

#include <algorithm>
#include <cmath>

#include "spinewatch/estimator/fit_flags.hpp"

namespace spinewatch {
namespace {

constexpr double kSecondsPerNs = 1e-9;

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

}  // namespace

ExposureAccumulator::ExposureAccumulator(ExposureOptions options) : options_(std::move(options)) {}

ExposureAccumulator::Sample ExposureAccumulator::sample_of(const Posture& p) const {
  Sample s;
  s.t_ns = p.t_ns;
  if (p.state == TrackingState::Tracking && p.ergonomics) {
    const Ergonomics& e = *p.ergonomics;
    const ErgonomicLimits& l = options_.limits;
    s.kind = Kind::Tracked;
    s.inclination_deg = e.trunk_inclination_deg;
    s.zone = inclination_zone(e.trunk_inclination_deg, l);
    s.lateral_deg = e.lateral_bend_deg;
    s.twist_deg = e.twist_deg;
    s.lateral_over = std::abs(e.lateral_bend_deg) > l.bend_twist_deg;
    s.twist_over = std::abs(e.twist_deg) > l.bend_twist_deg;
    s.twist_unresolved = p.fit.flag == kTwistUnresolvedFlag;
    s.reba = std::clamp(e.reba_trunk, 1, 5);
    s.rula = rula_trunk_score({e.trunk_inclination_deg, e.lateral_bend_deg, e.twist_deg}, l);
    for (const LevelLoad& load : p.loads)
      if (load.level == kVertebraNames[kWaistIndex]) s.compression_n = load.compression_n;
  } else if (p.state == TrackingState::Lost) {
    s.kind = p.fit.flag == "no_person" ? Kind::Empty : Kind::Lost;
  } else {
    s.kind = Kind::Init;  // building the model, or a tracking line without trunk angles
  }
  return s;
}

std::int64_t ExposureAccumulator::window_end(std::int64_t t) const {
  const std::int64_t i = options_.interval_ns;
  return (floor_div(t + options_.align_ns, i) + 1) * i - options_.align_ns;
}

void ExposureAccumulator::open(const Sample& first) {
  interval_ = Window{};
  shift_ = Window{};
  interval_.summary.scope = SummaryScope::Interval;
  shift_.summary.scope = SummaryScope::Shift;
  interval_.summary.start_ns = shift_.summary.start_ns = first.t_ns;
  for (Window* w : {&interval_, &shift_}) {
    w->summary.hold_limit_s = options_.limits.inclination_max_hold_s;
    w->summary.action_limit_n = options_.limits.niosh_action_limit_n;
    w->summary.bend_twist_limit_deg = options_.limits.bend_twist_deg;
  }
  interval_end_ns_ = window_end(first.t_ns);
  hold_start_ns_.reset();
  lateral_in_entry_ = twist_in_entry_ = false;
}

std::vector<ExposureSummary> ExposureAccumulator::add(const Posture& posture) {
  std::vector<ExposureSummary> out;
  Sample s = sample_of(posture);
  if (pending_ && s.t_ns < pending_->t_ns) out = finish();
  if (!pending_) {
    open(s);
    pending_ = s;
    return out;
  }
  const std::int64_t covered = std::min(s.t_ns, pending_->t_ns + options_.max_gap_ns);
  last_period_ns_ = covered - pending_->t_ns;
  credit(*pending_, pending_->t_ns, covered, out);
  if (covered < s.t_ns) credit_gap(covered, s.t_ns, out);
  pending_ = s;
  return out;
}

std::vector<ExposureSummary> ExposureAccumulator::finish() {
  std::vector<ExposureSummary> out;
  if (!pending_) return out;
  const std::int64_t end = pending_->t_ns + last_period_ns_;
  credit(*pending_, pending_->t_ns, end, out);
  // A window that the last frame filled exactly was closed by credit().
  if (interval_.summary.start_ns < end || out.empty()) close_window(end, true, out);
  pending_.reset();
  last_period_ns_ = 0;
  return out;
}

// Splits [a, b) at interval boundaries; a window whose end is reached is closed.
void ExposureAccumulator::credit(Sample& s, std::int64_t a, std::int64_t b, std::vector<ExposureSummary>& out) {
  for (;;) {
    const std::int64_t end = std::min(b, interval_end_ns_);
    integrate(s, a, end);
    if (b < interval_end_ns_) return;
    a = interval_end_ns_;
    close_window(interval_end_ns_, false, out);
    if (a == b) return;
  }
}

void ExposureAccumulator::credit_gap(std::int64_t a, std::int64_t b, std::vector<ExposureSummary>& out) {
  hold_start_ns_.reset();  // a hold is a run of tracked postures in the zone
  for (;;) {
    const std::int64_t end = std::min(b, interval_end_ns_);
    for (Window* w : {&interval_, &shift_}) w->summary.gap_s += double(end - a) * kSecondsPerNs;
    if (b < interval_end_ns_) return;
    a = interval_end_ns_;
    close_window(interval_end_ns_, false, out);
    if (a == b) return;
  }
}

void ExposureAccumulator::integrate(Sample& s, std::int64_t a, std::int64_t b) {
  if (!s.started) {
    // Events belong to the window holding the posture's own time.
    s.started = true;
    const bool tracked = s.kind == Kind::Tracked;
    if (tracked) {
      const ErgonomicLimits& l = options_.limits;
      const bool lateral_in = within_bend_twist_entry(lateral_in_entry_, s.lateral_deg, l);
      const bool twist_in = within_bend_twist_entry(twist_in_entry_, s.twist_deg, l);
      for (Window* w : {&interval_, &shift_}) {
        if (lateral_in && !lateral_in_entry_) ++w->summary.lateral_bend.entries;
        if (twist_in && !twist_in_entry_) ++w->summary.axial_twist.entries;
      }
      // Untracked postures leave the entry state as it was: not known.
      lateral_in_entry_ = lateral_in;
      twist_in_entry_ = twist_in;
    }
    if (tracked && s.zone == InclinationZone::Flexed) {
      if (!hold_start_ns_) hold_start_ns_ = s.t_ns;
    } else {
      hold_start_ns_.reset();
    }
  }
  if (b <= a) return;
  const double dt = double(b - a) * kSecondsPerNs;
  for (Window* w : {&interval_, &shift_}) {
    ExposureSummary& x = w->summary;
    switch (s.kind) {
      case Kind::Init: x.init_s += dt; continue;
      case Kind::Lost: x.lost_s += dt; continue;
      case Kind::Empty: x.empty_s += dt; continue;
      case Kind::Tracked: break;
    }
    x.tracked_s += dt;
    x.zone_s[std::size_t(s.zone)] += dt;
    w->inclination_integral += s.inclination_deg * dt;
    x.inclination_min_deg = w->any_tracked ? std::min(x.inclination_min_deg, s.inclination_deg) : s.inclination_deg;
    x.inclination_max_deg = w->any_tracked ? std::max(x.inclination_max_deg, s.inclination_deg) : s.inclination_deg;
    w->any_tracked = true;
    if (s.lateral_over) x.lateral_bend.over_s += dt;
    if (s.twist_over) x.axial_twist.over_s += dt;
    if (s.twist_unresolved) x.twist_unresolved_s += dt;
    x.reba_trunk_s[std::size_t(s.reba - 1)] += dt;
    x.rula_trunk_s[std::size_t(s.rula - 1)] += dt;
    if (hold_start_ns_) {
      const std::int64_t limit_at = *hold_start_ns_ + std::int64_t(std::llround(x.hold_limit_s * 1e9));
      if (b > limit_at) x.hold_beyond_s += double(b - std::max(a, limit_at)) * kSecondsPerNs;
      if (a <= limit_at && limit_at < b) ++x.holds_beyond;
      x.longest_hold_s = std::max(x.longest_hold_s, double(b - *hold_start_ns_) * kSecondsPerNs);
    }
    if (s.compression_n) {
      x.compression_based_on_s += dt;
      x.compression_peak_n = std::max(x.compression_peak_n, *s.compression_n);
      x.cumulative_n_s += *s.compression_n * dt;
      if (*s.compression_n > x.action_limit_n) x.above_action_limit_s += dt;
    }
  }
}

ExposureSummary ExposureAccumulator::finished(const Window& w) {
  ExposureSummary s = w.summary;
  s.inclination_mean_deg = s.tracked_s > 0 ? w.inclination_integral / s.tracked_s : 0.0;
  s.compression_mean_n = s.compression_based_on_s > 0 ? s.cumulative_n_s / s.compression_based_on_s : 0.0;
  return s;
}

void ExposureAccumulator::close_window(std::int64_t end_ns, bool partial, std::vector<ExposureSummary>& out) {
  interval_.summary.end_ns = end_ns;
  interval_.summary.partial = partial || end_ns - interval_.summary.start_ns < options_.interval_ns;
  shift_.summary.end_ns = end_ns;
  out.push_back(finished(interval_));
  out.push_back(finished(shift_));
  const ExposureSummary settings = interval_.summary;
  interval_ = Window{};
  interval_.summary.scope = SummaryScope::Interval;
  interval_.summary.start_ns = end_ns;
  interval_.summary.hold_limit_s = settings.hold_limit_s;
  interval_.summary.action_limit_n = settings.action_limit_n;
  interval_.summary.bend_twist_limit_deg = settings.bend_twist_limit_deg;
  interval_end_ns_ = end_ns + options_.interval_ns;
}

}  // namespace spinewatch
