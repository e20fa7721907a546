#pragma once
// Which postures an export takes: tracked ones, within a time range.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "spinewatch/export/opensim_files.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::exporting {

// A stream line with where it came from: `where` prefixes errors
// ("p.ndjson:12", "db row 7"); `stored_utc_ns` is the database's wall-clock
// time of the row (none for a file).
struct SourceLine {
  std::string text;
  std::string where;
  std::optional<std::int64_t> stored_utc_ns;
};

// [from, to): bounds on the stream's clock (ns of t_ns), or on UTC (ns
// since the epoch), which only the database's rows carry.
struct TimeRange {
  struct Bound {
    bool utc = false;
    std::int64_t ns = 0;
  };
  std::optional<Bound> from, to;
};

struct RowsRead {
  std::vector<PoseRow> rows;
  std::uint64_t postures = 0;  // posture lines within the range
  std::uint64_t omitted = 0;   // of those, not tracked (init, lost): no row
};

// The lines of an NDJSON file (a posture stream, replay --out, ground truth).
Result<std::vector<SourceLine>> read_ndjson_lines(const std::filesystem::path& path);
// Posture lines in the range, in stream order; other classes are skipped.
// Errors: a malformed posture line (its `where`), a UTC bound on lines
// without stored UTC times.
Result<RowsRead> select_rows(const std::vector<SourceLine>& lines, const TimeRange& range);

}  // namespace spinewatch::exporting
