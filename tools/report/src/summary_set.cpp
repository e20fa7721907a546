#include "spinewatch/report/summary_set.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>

#include <fmt/format.h>

namespace spinewatch::report {

Result<TimePoint> parse_time_point(std::string_view text) {
  if (text.find('T') != std::string_view::npos) {
    auto utc = parse_utc(text);
    if (!utc) return utc.error();
    return TimePoint{true, *utc};
  }
  double seconds = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), seconds);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(seconds))
    return Error{fmt::format("\"{}\": not a time (UTC like 2026-12-02T08:00:00Z, or seconds of the stream)", text)};
  return TimePoint{false, std::llround(seconds * 1e9)};
}

Result<Period> parse_period(std::string_view text) {
  const auto slash = text.find('/');
  if (slash == std::string_view::npos) return Error{fmt::format("\"{}\": expected FROM/TO", text)};
  auto from = parse_time_point(text.substr(0, slash));
  if (!from) return from.error();
  auto to = parse_time_point(text.substr(slash + 1));
  if (!to) return to.error();
  if (from->utc != to->utc) return Error{fmt::format("\"{}\": FROM and TO must both be UTC or both seconds", text)};
  if (to->ns <= from->ns) return Error{fmt::format("\"{}\": TO is not after FROM", text)};
  return Period{*from, *to, std::string(text)};
}

Result<std::vector<LabelledSummary>> read_summary_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return Error{fmt::format("{}: cannot be read", path.string())};
  std::vector<LabelledSummary> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    // Cheap test first: most lines of a recorded stream are postures.
    if (line.find("\"class\":\"summary\"") == std::string::npos) continue;
    auto s = decode_summary(line, fmt::format("{}:{}", path.string(), n));
    if (!s) return s.error();
    if (s->summary.scope == SummaryScope::Interval) out.push_back(std::move(s).value());
  }
  return out;
}

Result<bool> starts_within(const LabelledSummary& s, const std::optional<TimePoint>& from,
                           const std::optional<TimePoint>& to) {
  for (const auto* bound : {&from, &to}) {
    if (!*bound) continue;
    if ((*bound)->utc && !s.utc_start_ns())
      return Error{"a UTC time was given, but the summaries carry no UTC times (a replayed recording): give "
                   "seconds of the stream instead"};
  }
  auto time = [&](const TimePoint& p) { return p.utc ? *s.utc_start_ns() : s.summary.start_ns; };
  if (from && time(*from) < from->ns) return false;
  if (to && time(*to) >= to->ns) return false;
  return true;
}

Result<std::vector<LabelledSummary>> select(std::vector<LabelledSummary> all, const Selection& selection) {
  std::vector<LabelledSummary> out;
  for (auto& s : all) {
    if (selection.worker && s.labels.worker != selection.worker) continue;
    auto within = starts_within(s, selection.from, selection.to);
    if (!within) return within.error();
    if (*within) out.push_back(std::move(s));
  }
  return out;
}

ExposureSummary combine(std::span<const LabelledSummary> intervals) {
  ExposureSummary c;
  if (intervals.empty()) return c;
  c.start_ns = intervals.front().summary.start_ns;
  c.end_ns = intervals.back().summary.end_ns;
  double inclination_integral = 0;
  bool any_tracked = false;
  for (const LabelledSummary& l : intervals) {
    const ExposureSummary& s = l.summary;
    c.tracked_s += s.tracked_s;
    c.init_s += s.init_s;
    c.lost_s += s.lost_s;
    c.empty_s += s.empty_s;
    c.gap_s += s.gap_s;
    for (std::size_t z = 0; z < c.zone_s.size(); ++z) c.zone_s[z] += s.zone_s[z];
    inclination_integral += s.inclination_mean_deg * s.tracked_s;
    if (s.tracked_s > 0) {
      c.inclination_min_deg = any_tracked ? std::min(c.inclination_min_deg, s.inclination_min_deg) : s.inclination_min_deg;
      c.inclination_max_deg = any_tracked ? std::max(c.inclination_max_deg, s.inclination_max_deg) : s.inclination_max_deg;
      any_tracked = true;
    }
    c.bend_twist_limit_deg = s.bend_twist_limit_deg;
    for (auto [to, from] : {std::pair{&c.lateral_bend, &s.lateral_bend}, std::pair{&c.axial_twist, &s.axial_twist}}) {
      to->over_s += from->over_s;
      to->entries += from->entries;
    }
    c.hold_limit_s = s.hold_limit_s;
    c.hold_beyond_s += s.hold_beyond_s;
    c.holds_beyond += s.holds_beyond;
    c.longest_hold_s = std::max(c.longest_hold_s, s.longest_hold_s);
    for (std::size_t i = 0; i < c.reba_trunk_s.size(); ++i) c.reba_trunk_s[i] += s.reba_trunk_s[i];
    for (std::size_t i = 0; i < c.rula_trunk_s.size(); ++i) c.rula_trunk_s[i] += s.rula_trunk_s[i];
    c.compression_based_on_s += s.compression_based_on_s;
    c.compression_peak_n = std::max(c.compression_peak_n, s.compression_peak_n);
    c.action_limit_n = s.action_limit_n;
    c.above_action_limit_s += s.above_action_limit_s;
    c.cumulative_n_s += s.cumulative_n_s;
  }
  c.inclination_mean_deg = c.tracked_s > 0 ? inclination_integral / c.tracked_s : 0.0;
  c.compression_mean_n = c.compression_based_on_s > 0 ? c.cumulative_n_s / c.compression_based_on_s : 0.0;
  return c;
}

}  // namespace spinewatch::report
