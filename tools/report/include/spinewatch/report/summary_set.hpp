#pragma once
// The interval summaries a report is made from (docs/exposure.md): read
// from a summaries file (replay --summaries, a recorded stream) or the
// station's database, selected by time and worker, and added up.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/estimator/load/exposure_json.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::report {

// A time on the command line: UTC ("2026-12-02T08:00:00Z"), compared with
// the summaries' utc_start, or seconds of the stream's clock ("90.5"),
// compared with start_ns (a replayed recording has no UTC times).
struct TimePoint {
  bool utc = false;
  std::int64_t ns = 0;
};
Result<TimePoint> parse_time_point(std::string_view text);

// "FROM/TO": a period of the comparison figure.
struct Period {
  TimePoint from, to;
  std::string text;  // as given, for the legend
};
Result<Period> parse_period(std::string_view text);

struct Selection {
  std::optional<TimePoint> from, to;  // interval starts in [from, to)
  std::optional<std::string> worker;
};

// The interval lines of an NDJSON file, in order; every other line (shift
// summaries, postures, hello) is skipped. Errors name the file and line.
Result<std::vector<LabelledSummary>> read_summary_file(const std::filesystem::path& path);

// True when the interval starts within [from, to); an error when a UTC
// bound meets a summary without UTC times.
Result<bool> starts_within(const LabelledSummary& s, const std::optional<TimePoint>& from,
                           const std::optional<TimePoint>& to);
Result<std::vector<LabelledSummary>> select(std::vector<LabelledSummary> all, const Selection& selection);

// Several intervals as one: times and counts added, peaks and extremes
// kept, means weighted by the time they are based on.
ExposureSummary combine(std::span<const LabelledSummary> intervals);

}  // namespace spinewatch::report
