#pragma once
// The exposure report (spinewatch report, docs/exposure.md): one
// self-contained HTML page with inline SVG figures, and the intervals as
// CSV. Every figure's marks carry their figure as data-* attributes, so a
// test can check what a browser shows against the summaries.
#include <optional>
#include <string>
#include <vector>

#include "spinewatch/report/summary_set.hpp"

namespace spinewatch::report {

struct ReportInput {
  std::vector<LabelledSummary> intervals;  // selected, in time order
  // The comparison figure's two periods; without them, the first and the
  // second half of the intervals.
  std::optional<Period> period_a, period_b;
  std::string source;     // "summaries FILE" or "database FILE"
  std::string selection;  // what was asked for, in words
};

Result<std::string> render_html(const ReportInput& input);
// One row per interval; the header names every column with its unit.
std::string render_csv(const std::vector<LabelledSummary>& intervals);

}  // namespace spinewatch::report
