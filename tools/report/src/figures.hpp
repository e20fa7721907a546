#pragma once
// The report's figures, each an inline <svg> (html_report.cpp puts them
// on the page). Private to the report library.
#include <string>
#include <vector>

#include "spinewatch/report/summary_set.hpp"

namespace spinewatch::report {

// Time axis shared by the time figures: seconds from the first interval's start.
struct TimeAxis {
  std::int64_t start_ns = 0, end_ns = 0;
  std::optional<std::int64_t> utc_offset_ns;  // labels in UTC when known
  std::string label(std::int64_t t_ns) const;
};
TimeAxis time_axis(const std::vector<LabelledSummary>& intervals);

std::string inclination_figure(const std::vector<LabelledSummary>& intervals, const TimeAxis& axis);
std::string zone_figure(const ExposureSummary& total);
std::string load_figure(const std::vector<LabelledSummary>& intervals, const TimeAxis& axis);
std::string reba_strip(const std::vector<LabelledSummary>& intervals, const TimeAxis& axis);
std::string comparison_figure(const ExposureSummary& a, const ExposureSummary& b, const std::string& label_a,
                              const std::string& label_b);

// Time-weighted mean REBA trunk score of tracked time (0 when none).
double mean_reba(const ExposureSummary& s);

}  // namespace spinewatch::report
