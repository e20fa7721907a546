#include <fmt/format.h>

#include "spinewatch/report/html_report.hpp"

namespace spinewatch::report {
namespace {

// RFC 4180: quoted when it holds a comma, quote or line break.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

std::string render_csv(const std::vector<LabelledSummary>& intervals) {
  std::string out =
      "utc_start,utc_end,start_ns,end_ns,duration_s,partial,station,worker,tracked_s,init_s,lost_s,empty_s,gap_s,"
      "extension_s,zone_0_20_s,zone_20_60_s,over_60_s,inclination_mean_deg,inclination_min_deg,inclination_max_deg,"
      "lateral_bend_over_s,lateral_bend_entries,axial_twist_over_s,axial_twist_entries,hold_limit_s,hold_beyond_s,"
      "holds_beyond,longest_hold_s,reba_1_s,reba_2_s,reba_3_s,reba_4_s,reba_5_s,rula_1_s,rula_2_s,rula_3_s,rula_4_s,"
      "rula_5_s,rula_6_s,l5_based_on_s,l5_peak_n,l5_mean_n,action_limit_n,above_action_limit_s,cumulative_n_s\n";
  for (const LabelledSummary& l : intervals) {
    const ExposureSummary& s = l.summary;
    const auto utc = l.labels.utc_offset_ns;
    out += fmt::format("{},{},{},{},{:.6f},{},{},{},", utc ? format_utc(s.start_ns + *utc) : "",
                       utc ? format_utc(s.end_ns + *utc) : "", s.start_ns, s.end_ns, s.duration_s(),
                       s.partial ? "true" : "false", csv_field(l.labels.station.value_or("")),
                       csv_field(l.labels.worker.value_or("")));
    out += fmt::format("{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},", s.tracked_s, s.init_s, s.lost_s, s.empty_s, s.gap_s);
    for (double z : s.zone_s) out += fmt::format("{:.6f},", z);
    out += fmt::format("{:.2f},{:.2f},{:.2f},", s.inclination_mean_deg, s.inclination_min_deg, s.inclination_max_deg);
    out += fmt::format("{:.6f},{},{:.6f},{},", s.lateral_bend.over_s, s.lateral_bend.entries, s.axial_twist.over_s,
                       s.axial_twist.entries);
    out += fmt::format("{},{:.6f},{},{:.6f},", s.hold_limit_s, s.hold_beyond_s, s.holds_beyond, s.longest_hold_s);
    for (double r : s.reba_trunk_s) out += fmt::format("{:.6f},", r);
    for (double r : s.rula_trunk_s) out += fmt::format("{:.6f},", r);
    out += fmt::format("{:.6f},{:.1f},{:.1f},{},{:.6f},{:.1f}\n", s.compression_based_on_s, s.compression_peak_n,
                       s.compression_mean_n, s.action_limit_n, s.above_action_limit_s, s.cumulative_n_s);
  }
  return out;
}

}  // namespace spinewatch::report
