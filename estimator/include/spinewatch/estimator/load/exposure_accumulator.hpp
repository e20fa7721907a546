#pragma once
// Turns the posture stream into exposure summaries (docs/exposure.md): one
// per interval, aligned to multiples of the interval, each followed by the
// summary of the whole shift so far. Pure computation, cheap per pair (a
// few additions); one instance per stream, not thread-safe.
//
// Each posture stands for the time until the next one (at most max_gap;
// beyond that the time is a gap), split exactly at interval boundaries, so
// the coverage figures of a window add up to its length.
#include <cstdint>
#include <optional>
#include <vector>

#include "spinewatch/estimator/load/exposure_summary.hpp"
#include "spinewatch/estimator/posture.hpp"

namespace spinewatch {

struct ExposureOptions {
  std::int64_t interval_ns = 60'000'000'000;
  // Boundaries fall where (t + align_ns) is a multiple of interval_ns: the
  // daemon passes CLOCK_REALTIME − CLOCK_MONOTONIC so intervals are whole
  // wall-clock minutes.
  std::int64_t align_ns = 0;
  std::int64_t max_gap_ns = 1'000'000'000;
  ErgonomicLimits limits = default_ergonomic_limits();
};

class ExposureAccumulator {
 public:
  explicit ExposureAccumulator(ExposureOptions options = {});

  // Postures in time order. Returns what this one closed: each completed
  // interval, each followed by the shift summary up to its end. A posture
  // earlier than the last one (a clock that went back) ends the shift as
  // finish() does and starts a new one.
  std::vector<ExposureSummary> add(const Posture& posture);
  // Ends the stream: the last posture stands for the last frame period;
  // returns the last (partial) interval and the shift summary. The
  // accumulator starts afresh with the next add().
  std::vector<ExposureSummary> finish();

  const ExposureOptions& options() const { return options_; }

 private:
  enum class Kind : std::uint8_t { Tracked, Init, Lost, Empty };
  struct Sample {
    std::int64_t t_ns = 0;
    Kind kind = Kind::Init;
    InclinationZone zone = InclinationZone::Upright;
    double inclination_deg = 0;
    double lateral_deg = 0, twist_deg = 0;
    bool lateral_over = false, twist_over = false;  // beyond the limit (time beyond)
    bool twist_unresolved = false;  // fit.flag "twist_unresolved"
    int reba = 1, rula = 1;
    std::optional<double> compression_n;
    bool started = false;  // its first segment was credited (entries counted)
  };
  struct Window {
    ExposureSummary summary;
    double inclination_integral = 0;  // deg·s
    bool any_tracked = false;
  };

  Sample sample_of(const Posture& posture) const;
  void open(const Sample& first);
  void credit(Sample& s, std::int64_t a, std::int64_t b, std::vector<ExposureSummary>& out);
  void credit_gap(std::int64_t a, std::int64_t b, std::vector<ExposureSummary>& out);
  void integrate(Sample& s, std::int64_t a, std::int64_t b);
  void close_window(std::int64_t end_ns, bool partial, std::vector<ExposureSummary>& out);
  std::int64_t window_end(std::int64_t t) const;
  static ExposureSummary finished(const Window& w);

  ExposureOptions options_;
  std::optional<Sample> pending_;
  std::int64_t last_period_ns_ = 0;
  Window interval_, shift_;
  std::int64_t interval_end_ns_ = 0;
  // State carried across samples.
  std::optional<std::int64_t> hold_start_ns_;  // the running 20–60° hold
  bool lateral_in_entry_ = false, twist_in_entry_ = false;  // within_bend_twist_entry
};

}  // namespace spinewatch
