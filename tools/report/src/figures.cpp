#include "figures.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>

#include <fmt/format.h>

#include "spinewatch/report/svg.hpp"

namespace spinewatch::report {
namespace {

constexpr int kWidth = 760;
constexpr std::array<const char*, 4> kZoneColours = {"#6fa8dc", "#93c47d", "#f6b26b", "#e06666"};
constexpr std::array<const char*, 4> kZoneNames = {"extension (< 0°)", "0–20°", "20–60°", "> 60°"};

double seconds_since(const TimeAxis& axis, std::int64_t t_ns) { return double(t_ns - axis.start_ns) * 1e-9; }
double mid_ns(const ExposureSummary& s) { return 0.5 * double(s.start_ns + s.end_ns); }

// Ticks at a round step so there are about six.
double tick_step(double span) {
  for (double step : {1.0, 2.0, 5.0, 10.0, 15.0, 30.0, 60.0, 120.0, 300.0, 600.0, 900.0, 1800.0, 3600.0, 7200.0})
    if (span / step <= 8) return step;
  return 14400.0;
}

void time_ticks(SvgCanvas& c, const Scale& x, const TimeAxis& axis) {
  const double span = seconds_since(axis, axis.end_ns);
  const double step = tick_step(span);
  for (double t = 0; t <= span + 1e-9; t += step)
    c.x_tick(x(t), axis.label(axis.start_ns + std::llround(t * 1e9)));
}

std::string reba_colour(double mean) {  // 1 green … 3 amber … 5 red
  const double u = std::clamp((mean - 1.0) / 4.0, 0.0, 1.0);
  const int r = int(std::lround(u < 0.5 ? 80 + 2 * u * (240 - 80) : 240));
  const int g = int(std::lround(u < 0.5 ? 180 + 2 * u * (190 - 180) : 190 - 2 * (u - 0.5) * (190 - 60)));
  return fmt::format("rgb({},{},70)", r, g);
}

}  // namespace

std::string TimeAxis::label(std::int64_t t_ns) const {
  if (utc_offset_ns) {
    const std::time_t t = std::time_t((t_ns + *utc_offset_ns) / 1'000'000'000);
    std::tm tm{};
    ::gmtime_r(&t, &tm);
    return double(end_ns - start_ns) * 1e-9 < 600 ? fmt::format("{:02}:{:02}:{:02}", tm.tm_hour, tm.tm_min, tm.tm_sec)
                                                  : fmt::format("{:02}:{:02}", tm.tm_hour, tm.tm_min);
  }
  const auto s = std::llround(double(t_ns - start_ns) * 1e-9);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

TimeAxis time_axis(const std::vector<LabelledSummary>& intervals) {
  TimeAxis a;
  if (intervals.empty()) return a;
  a.start_ns = intervals.front().summary.start_ns;
  a.end_ns = intervals.back().summary.end_ns;
  a.utc_offset_ns = intervals.front().labels.utc_offset_ns;
  return a;
}

double mean_reba(const ExposureSummary& s) {
  double weighted = 0, total = 0;
  for (std::size_t i = 0; i < s.reba_trunk_s.size(); ++i) {
    weighted += double(i + 1) * s.reba_trunk_s[i];
    total += s.reba_trunk_s[i];
  }
  return total > 0 ? weighted / total : 0.0;
}

std::string inclination_figure(const std::vector<LabelledSummary>& intervals, const TimeAxis& axis) {
  SvgCanvas c("fig-inclination", kWidth, 280, 56, 20, 16, 30, "Trunk inclination over time");
  double lo = -20, hi = 90;
  for (const auto& l : intervals)
    if (l.summary.tracked_s > 0) {
      lo = std::min(lo, l.summary.inclination_min_deg - 5);
      hi = std::max(hi, l.summary.inclination_max_deg + 5);
    }
  const Scale x = c.x_scale(0, std::max(1e-9, seconds_since(axis, axis.end_ns)));
  const Scale y = c.y_scale(lo, hi);
  // The ISO 11226 zones behind the data (the extension margin aside).
  const std::array<double, 5> edges = {lo, 0, 20, 60, hi};
  for (std::size_t z = 0; z < 4; ++z)
    c.rect(c.plot_left(), y(edges[z + 1]), c.plot_right() - c.plot_left(), y(edges[z]) - y(edges[z + 1]),
           kZoneColours[z], "opacity=\"0.18\"");
  for (double d = std::ceil(lo / 20) * 20; d <= hi; d += 20) c.y_tick(y(d), fmt::format("{:.0f}°", d));
  time_ticks(c, x, axis);
  std::string points;
  for (const auto& l : intervals) {
    const ExposureSummary& s = l.summary;
    if (s.tracked_s <= 0) continue;  // nothing tracked: no point, a gap in the line
    const double px = x(seconds_since(axis, std::llround(mid_ns(s))));
    c.line(px, y(s.inclination_min_deg), px, y(s.inclination_max_deg), "#555", 1,
           fmt::format("class=\"incl-range\" data-start-ns=\"{}\" data-min-deg=\"{:.2f}\" data-max-deg=\"{:.2f}\"",
                       s.start_ns, s.inclination_min_deg, s.inclination_max_deg));
    c.circle(px, y(s.inclination_mean_deg), 3, "#1f4e79",
             fmt::format("class=\"incl-mean\" data-start-ns=\"{}\" data-deg=\"{:.2f}\"", s.start_ns,
                         s.inclination_mean_deg));
    points += fmt::format("{:.2f},{:.2f} ", px, y(s.inclination_mean_deg));
  }
  c.polyline(points, "#1f4e79", 1.5);
  c.text(c.plot_left() + 6, c.plot_top() + 12, "mean per interval (dot) and its range (bar), degrees forward of upright");
  return c.str();
}

std::string zone_figure(const ExposureSummary& total) {
  SvgCanvas c("fig-zones", kWidth, 170, 130, 200, 10, 10, "Time in each trunk-inclination zone");
  const double most = std::max(1e-9, *std::max_element(total.zone_s.begin(), total.zone_s.end()));
  const double row = (c.plot_bottom() - c.plot_top()) / 4.0;
  const double full = c.plot_right() - c.plot_left();
  for (std::size_t z = 0; z < 4; ++z) {
    const double y = c.plot_top() + double(z) * row;
    const double s = total.zone_s[z];
    const double w = full * s / most;
    c.text(c.plot_left() - 8, y + row * 0.62, kZoneNames[z], "end", 12);
    c.rect(c.plot_left(), y + row * 0.15, w, row * 0.7, kZoneColours[z],
           fmt::format("class=\"zone-bar\" data-zone=\"{}\" data-seconds=\"{:.6f}\"", zone_key(InclinationZone(z)), s));
    const double pct = total.tracked_s > 0 ? 100.0 * s / total.tracked_s : 0.0;
    c.text(c.plot_left() + w + 6, y + row * 0.62, fmt::format("{} · {:.1f} % of tracked",
                                                             s < 60.0 ? fmt::format("{:.1f} s", s) : fmt::format("{:.1f} min", s / 60.0), pct),
           "start", 11);
  }
  return c.str();
}

std::string load_figure(const std::vector<LabelledSummary>& intervals, const TimeAxis& axis) {
  SvgCanvas c("fig-load", kWidth, 260, 56, 20, 16, 30, "Compression at L5 over time");
  double hi = 0, limit = 3400;
  for (const auto& l : intervals) {
    hi = std::max(hi, l.summary.compression_peak_n);
    if (l.summary.action_limit_n > 0) limit = l.summary.action_limit_n;
  }
  hi = std::max(hi, limit) * 1.1;
  const Scale x = c.x_scale(0, std::max(1e-9, seconds_since(axis, axis.end_ns)));
  const Scale y = c.y_scale(0, hi);
  const double step = hi > 5000 ? 1000 : 500;
  for (double n = 0; n <= hi; n += step) c.y_tick(y(n), fmt::format("{:.0f} N", n));
  time_ticks(c, x, axis);
  c.line(c.plot_left(), y(limit), c.plot_right(), y(limit), "#cc0000", 1.5,
         fmt::format("class=\"action-limit\" data-n=\"{}\" stroke-dasharray=\"6 4\"", limit));
  c.text(c.plot_right() - 4, y(limit) - 4, fmt::format("NIOSH action limit {:.0f} N", limit), "end", 10,
         "fill=\"#cc0000\"");
  std::string means;
  for (const auto& l : intervals) {
    const ExposureSummary& s = l.summary;
    if (s.compression_based_on_s <= 0) continue;
    const double px = x(seconds_since(axis, std::llround(mid_ns(s))));
    c.circle(px, y(s.compression_peak_n), 3, "#990000",
             fmt::format("class=\"load-peak\" data-start-ns=\"{}\" data-n=\"{:.1f}\"", s.start_ns, s.compression_peak_n));
    c.circle(px, y(s.compression_mean_n), 2.5, "#38761d",
             fmt::format("class=\"load-mean\" data-start-ns=\"{}\" data-n=\"{:.1f}\"", s.start_ns, s.compression_mean_n));
    means += fmt::format("{:.2f},{:.2f} ", px, y(s.compression_mean_n));
  }
  c.polyline(means, "#38761d", 1.5);
  c.text(c.plot_left() + 6, c.plot_top() + 12, "per interval: mean (green line) and peak (red dots)");
  return c.str();
}

std::string reba_strip(const std::vector<LabelledSummary>& intervals, const TimeAxis& axis) {
  SvgCanvas c("fig-reba", kWidth, 96, 56, 20, 10, 30, "REBA trunk score per interval");
  const Scale x = c.x_scale(0, std::max(1e-9, seconds_since(axis, axis.end_ns)));
  time_ticks(c, x, axis);
  for (const auto& l : intervals) {
    const ExposureSummary& s = l.summary;
    const double x0 = x(seconds_since(axis, s.start_ns)), x1 = x(seconds_since(axis, s.end_ns));
    const double mean = mean_reba(s);
    std::string dist;
    for (double v : s.reba_trunk_s) dist += fmt::format("{}{:.3f}", dist.empty() ? "" : ",", v);
    const std::string fill = mean > 0 ? reba_colour(mean) : "#cccccc";
    c.raw(fmt::format(
        "<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"{}\" class=\"reba-cell\" "
        "data-start-ns=\"{}\" data-mean=\"{:.3f}\" data-dist=\"{}\"><title>{}: mean REBA trunk score {:.2f}; "
        "seconds at 1…5: {}</title></rect>\n",
        x0, c.plot_top(), std::max(0.5, x1 - x0), c.plot_bottom() - c.plot_top(), fill, s.start_ns, mean, dist,
        escape_xml(axis.label(s.start_ns)), mean, dist));
  }
  return c.str();
}

std::string comparison_figure(const ExposureSummary& a, const ExposureSummary& b, const std::string& label_a,
                              const std::string& label_b) {
  SvgCanvas c("fig-compare", kWidth, 240, 56, 20, 28, 30, "Time in each zone: period A against period B");
  const Scale y = c.y_scale(0, 100);
  for (int p = 0; p <= 100; p += 20) c.y_tick(y(p), fmt::format("{} %", p));
  const double group = (c.plot_right() - c.plot_left()) / 4.0;
  for (std::size_t z = 0; z < 4; ++z) {
    const double gx = c.plot_left() + double(z) * group;
    std::size_t k = 0;
    for (auto [s, key, colour] : {std::tuple{&a, "a", "#1f4e79"}, std::tuple{&b, "b", "#e69138"}}) {
      const double pct = s->tracked_s > 0 ? 100.0 * s->zone_s[z] / s->tracked_s : 0.0;
      const double bx = gx + group * (0.15 + 0.36 * double(k++));
      c.rect(bx, y(pct), group * 0.32, y(0) - y(pct), colour,
             fmt::format("class=\"cmp-bar\" data-period=\"{}\" data-zone=\"{}\" data-percent=\"{:.3f}\"", key,
                         zone_key(InclinationZone(z)), pct));
      c.text(bx + group * 0.16, y(pct) - 3, fmt::format("{:.1f}", pct), "middle", 10);
    }
    c.text(gx + group / 2, c.plot_bottom() + 16, kZoneNames[z], "middle", 11);
  }
  c.rect(c.plot_left() + 8, 8, 10, 10, "#1f4e79");
  c.text(c.plot_left() + 22, 17, "A: " + label_a, "start", 11);
  c.rect(c.plot_left() + 380, 8, 10, 10, "#e69138");
  c.text(c.plot_left() + 394, 17, "B: " + label_b, "start", 11);
  return c.str();
}

}  // namespace spinewatch::report
