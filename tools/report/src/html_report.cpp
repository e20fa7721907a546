#include "spinewatch/report/html_report.hpp"

#include <fmt/format.h>

#include "figures.hpp"
#include "spinewatch/report/svg.hpp"

namespace spinewatch::report {
namespace {

constexpr const char* kZoneLabels[] = {"in extension", "at 0–20°", "at 20–60°", "beyond 60°"};

// Minutes over a shift; seconds for the short recordings a first try makes (not "0.0 min").
std::string minutes(double s) { return s < 60.0 ? fmt::format("{:.1f} s", s) : fmt::format("{:.1f} min", s / 60.0); }
std::string share(double s, double of) { return of > 0 ? fmt::format("{:.1f} %", 100.0 * s / of) : "–"; }

// The rows of the key-figures table, for one or two columns.
std::string key_rows(const std::vector<const ExposureSummary*>& cols) {
  std::string out;
  auto row = [&](std::string_view name, auto cell) {
    out += fmt::format("<tr><th>{}</th>", escape_xml(name));
    for (const ExposureSummary* s : cols) out += "<td>" + escape_xml(cell(*s)) + "</td>";
    out += "</tr>\n";
  };
  row("tracked (figures below are based on it)", [](const ExposureSummary& s) { return minutes(s.tracked_s); });
  row("building the model (init)", [](const ExposureSummary& s) { return minutes(s.init_s); });
  row("someone in view, not tracked (lost)", [](const ExposureSummary& s) { return minutes(s.lost_s); });
  row("nobody in view (empty)", [](const ExposureSummary& s) { return minutes(s.empty_s); });
  row("no pairs (gap)", [](const ExposureSummary& s) { return minutes(s.gap_s); });
  for (std::size_t z = 0; z < kInclinationZoneCount; ++z)
    row(fmt::format("trunk {} (ISO 11226)", kZoneLabels[z]), [z](const ExposureSummary& s) {
      return fmt::format("{} ({})", minutes(s.zone_s[z]), share(s.zone_s[z], s.tracked_s));
    });
  row("side bend beyond 10°: entries per minute", [](const ExposureSummary& s) {
    return fmt::format("{:.2f} ({} in all, {:.0f} s beyond)", s.lateral_bend.per_minute(s.tracked_s),
                       s.lateral_bend.entries, s.lateral_bend.over_s);
  });
  row("axial twist beyond 10°: entries per minute", [](const ExposureSummary& s) {
    return fmt::format("{:.2f} ({} in all, {:.0f} s beyond)", s.axial_twist.per_minute(s.tracked_s),
                       s.axial_twist.entries, s.axial_twist.over_s);
  });
  row("20–60° holds beyond the holding limit", [](const ExposureSummary& s) {
    return fmt::format("{} holds, {:.0f} s beyond {:.0f} s; longest {:.0f} s", s.holds_beyond, s.hold_beyond_s,
                       s.hold_limit_s, s.longest_hold_s);
  });
  row("REBA trunk score, time-weighted mean", [](const ExposureSummary& s) { return fmt::format("{:.2f}", mean_reba(s)); });
  row("L5 compression: peak", [](const ExposureSummary& s) { return fmt::format("{:.0f} N", s.compression_peak_n); });
  row("L5 compression: mean", [](const ExposureSummary& s) { return fmt::format("{:.0f} N", s.compression_mean_n); });
  row("time above the NIOSH action limit", [](const ExposureSummary& s) {
    return fmt::format("{:.0f} s ({})", s.above_action_limit_s, share(s.above_action_limit_s, s.compression_based_on_s));
  });
  row("cumulative L5 load", [](const ExposureSummary& s) { return fmt::format("{:.3g} N·s", s.cumulative_n_s); });
  return out;
}

struct Halves {
  std::vector<LabelledSummary> a, b;
  std::string label_a, label_b;
};

Result<Halves> comparison_periods(const ReportInput& in) {
  Halves h;
  if (in.period_a && in.period_b) {
    for (const auto& [period, out] : {std::pair{&*in.period_a, &h.a}, std::pair{&*in.period_b, &h.b}})
      for (const auto& s : in.intervals) {
        auto within = starts_within(s, period->from, period->to);
        if (!within) return within.error();
        if (*within) out->push_back(s);
      }
    h.label_a = in.period_a->text;
    h.label_b = in.period_b->text;
    return h;
  }
  const std::size_t half = in.intervals.size() / 2;
  h.a.assign(in.intervals.begin(), in.intervals.begin() + std::ptrdiff_t(half));
  h.b.assign(in.intervals.begin() + std::ptrdiff_t(half), in.intervals.end());
  const TimeAxis axis = time_axis(in.intervals);
  auto span = [&](const std::vector<LabelledSummary>& v) {
    return v.empty() ? std::string("nothing")
                     : axis.label(v.front().summary.start_ns) + " – " + axis.label(v.back().summary.end_ns);
  };
  h.label_a = "first half, " + span(h.a);
  h.label_b = "second half, " + span(h.b);
  return h;
}

constexpr const char* kStyle = R"(
body { font-family: sans-serif; margin: 24px; color: #222; max-width: 820px; }
h1 { font-size: 22px; margin-bottom: 4px; }
h2 { font-size: 16px; margin-top: 28px; }
p.meta { color: #555; margin-top: 0; }
table { border-collapse: collapse; font-size: 13px; }
th, td { border-bottom: 1px solid #ddd; padding: 3px 10px 3px 0; text-align: left; vertical-align: top; }
th { font-weight: normal; color: #444; }
figure { margin: 12px 0 20px 0; }
figcaption { font-size: 12px; color: #555; max-width: 760px; }
)";

}  // namespace

Result<std::string> render_html(const ReportInput& in) {
  if (in.intervals.empty()) return Error{"no interval summaries in the selection: nothing to report"};
  const TimeAxis axis = time_axis(in.intervals);
  const ExposureSummary total = combine(in.intervals);
  auto halves = comparison_periods(in);
  if (!halves) return halves.error();
  const ExposureSummary a = combine(halves->a), b = combine(halves->b);

  std::string stations, workers;
  for (const auto& s : in.intervals) {
    if (s.labels.station && stations.find(*s.labels.station) == std::string::npos)
      stations += (stations.empty() ? "" : ", ") + *s.labels.station;
    if (s.labels.worker && workers.find(*s.labels.worker) == std::string::npos)
      workers += (workers.empty() ? "" : ", ") + *s.labels.worker;
  }
  const auto utc = in.intervals.front().labels.utc_offset_ns;
  const std::string from = utc ? format_utc(total.start_ns + *utc) : fmt::format("{:.1f} s", total.start_ns * 1e-9);
  const auto end_utc = in.intervals.back().labels.utc_offset_ns;
  const std::string to = end_utc ? format_utc(total.end_ns + *end_utc) : fmt::format("{:.1f} s", total.end_ns * 1e-9);

  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<title>Exposure report</title>\n<style>" + std::string(kStyle) + "</style>\n</head>\n<body>\n";
  html += "<h1>Exposure report</h1>\n";
  html += fmt::format(
      "<p class=\"meta\" id=\"meta\" data-intervals=\"{}\" data-tracked-s=\"{:.6f}\">Station {} · worker {} · {} to {} · "
      "{} intervals from {} · {}</p>\n",
      in.intervals.size(), total.tracked_s, escape_xml(stations.empty() ? "not named" : stations),
      escape_xml(workers.empty() ? "not named" : workers), escape_xml(from), escape_xml(to), in.intervals.size(),
      escape_xml(in.source), escape_xml(in.selection));
  html += "<h2>Key figures</h2>\n<table id=\"key-figures\">\n" + key_rows({&total}) + "</table>\n";
  html += "<h2>Trunk inclination over time</h2>\n<figure>" + inclination_figure(in.intervals, axis) +
          "<figcaption>Forward tilt of the line from L5 to T1 against the worker's upright posture, per interval: "
          "the dot is the time-weighted mean, the bar the range. Bands: ISO 11226 zones (extension, 0–20°, "
          "20–60°, above 60°). Intervals with nothing tracked have no dot.</figcaption></figure>\n";
  html += "<h2>Time in each zone</h2>\n<figure>" + zone_figure(total) +
          "<figcaption>Tracked time in each ISO 11226 trunk-inclination zone over the whole selection.</figcaption></figure>\n";
  html += "<h2>Load over time</h2>\n<figure>" + load_figure(in.intervals, axis) +
          "<figcaption>Compressive force on L5 (Schultz's equilibrium from the posture and the worker's mass), "
          "mean and peak per interval, against the NIOSH 1981 action limit.</figcaption></figure>\n";
  html += "<h2>REBA trunk score per interval</h2>\n<figure>" + reba_strip(in.intervals, axis) +
          "<figcaption>Each cell is one interval, coloured by its time-weighted mean REBA trunk score (1 green, "
          "3 amber, 5 red; grey: nothing tracked). Hover for the seconds at each score.</figcaption></figure>\n";
  html += "<h2>Comparison of two periods</h2>\n<figure>" + comparison_figure(a, b, halves->label_a, halves->label_b) +
          "<figcaption>Share of each period's tracked time in each zone.</figcaption></figure>\n";
  html += fmt::format("<table id=\"compare-figures\">\n<tr><th></th><td>A: {}</td><td>B: {}</td></tr>\n",
                      escape_xml(halves->label_a), escape_xml(halves->label_b)) +
          key_rows({&a, &b}) + "</table>\n";
  html += "<p class=\"meta\">Definitions, standards and formulas: docs/exposure.md of spinewatch. "
          "The intervals are in summaries.csv beside this page.</p>\n</body>\n</html>\n";
  return html;
}

}  // namespace spinewatch::report
