#include "spinewatch/estimator/load/exposure_json.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "spinewatch/estimator/posture_json.hpp"

#include "common/json_number.hpp"

namespace spinewatch {
namespace {
using nlohmann::json;
using ojson = nlohmann::ordered_json;

using detail::round_to;
double seconds(double s) { return round_to(s, 1e-6); }

ojson beyond_json(const BeyondLimit& b, double limit_deg, double tracked_s) {
  return {{"limit_deg", limit_deg},
          {"over_s", seconds(b.over_s)},
          {"entries", b.entries},
          {"per_minute", round_to(b.per_minute(tracked_s), 1e-3)}};
}

template <std::size_t N>
ojson seconds_array(const std::array<double, N>& a) {
  ojson out = ojson::array();
  for (double s : a) out.push_back(seconds(s));
  return out;
}

}  // namespace

std::string format_utc(std::int64_t unix_ns) {
  const std::int64_t s = unix_ns >= 0 ? unix_ns / 1'000'000'000 : (unix_ns - 999'999'999) / 1'000'000'000;
  const auto ms = (unix_ns - s * 1'000'000'000) / 1'000'000;
  const std::time_t t = static_cast<std::time_t>(s);
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                     tm.tm_hour, tm.tm_min, tm.tm_sec, ms);
}

Result<std::int64_t> parse_utc(std::string_view text) {
  const std::string s(text);
  std::tm tm{};
  int consumed = 0;
  if (std::sscanf(s.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%n", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour,
                  &tm.tm_min, &tm.tm_sec, &consumed) != 6)
    return Error{fmt::format("\"{}\": not a UTC time like 2026-12-02T07:55:00Z", s)};
  std::int64_t frac_ns = 0;
  std::size_t i = std::size_t(consumed);
  if (i < s.size() && s[i] == '.') {
    std::int64_t scale = 100'000'000;
    for (++i; i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])); ++i, scale /= 10)
      frac_ns += (s[i] - '0') * scale;
  }
  if (i + 1 != s.size() || s[i] != 'Z') return Error{fmt::format("\"{}\": expected a UTC time ending in Z", s)};
  if (tm.tm_mon < 1 || tm.tm_mon > 12 || tm.tm_mday < 1 || tm.tm_mday > 31 || tm.tm_hour > 23 || tm.tm_min > 59 ||
      tm.tm_sec > 60)
    return Error{fmt::format("\"{}\": a field is out of range", s)};
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  return std::int64_t(::timegm(&tm)) * 1'000'000'000 + frac_ns;
}

ojson to_json(const ExposureSummary& s, const SummaryLabels& labels) {
  ojson j = {{"class", "summary"},
             {"v", kPostureSchemaVersion},
             {"scope", std::string(to_string(s.scope))},
             {"start_ns", s.start_ns},
             {"end_ns", s.end_ns},
             {"duration_s", seconds(s.duration_s())},
             {"partial", s.partial}};
  if (labels.utc_offset_ns) {
    j["utc_start"] = format_utc(s.start_ns + *labels.utc_offset_ns);
    j["utc_end"] = format_utc(s.end_ns + *labels.utc_offset_ns);
  }
  if (labels.station) j["station"] = *labels.station;
  if (labels.worker) j["worker"] = *labels.worker;
  j["coverage"] = {{"tracked_s", seconds(s.tracked_s)}, {"init_s", seconds(s.init_s)}, {"lost_s", seconds(s.lost_s)},
                   {"empty_s", seconds(s.empty_s)},     {"gap_s", seconds(s.gap_s)}};
  ojson zones = ojson::object();
  for (std::size_t z = 0; z < kInclinationZoneCount; ++z)
    zones[std::string(zone_key(InclinationZone(z)))] = seconds(s.zone_s[z]);
  j["trunk_inclination"] = {{"zones_s", zones},
                            {"mean_deg", round_to(s.inclination_mean_deg, 0.01)},
                            {"min_deg", round_to(s.inclination_min_deg, 0.01)},
                            {"max_deg", round_to(s.inclination_max_deg, 0.01)}};
  j["lateral_bend"] = beyond_json(s.lateral_bend, s.bend_twist_limit_deg, s.tracked_s);
  j["axial_twist"] = beyond_json(s.axial_twist, s.bend_twist_limit_deg, s.tracked_s);
  j["axial_twist"]["unresolved_s"] = seconds(s.twist_unresolved_s);
  j["holding"] = {{"zone", "20_60"},
                  {"limit_s", s.hold_limit_s},
                  {"beyond_s", seconds(s.hold_beyond_s)},
                  {"holds_beyond", s.holds_beyond},
                  {"longest_s", seconds(s.longest_hold_s)}};
  j["reba_trunk_s"] = seconds_array(s.reba_trunk_s);
  j["rula_trunk_s"] = seconds_array(s.rula_trunk_s);
  j["lumbar_compression"] = {{"level", std::string(kVertebraNames[kWaistIndex])},
                             {"based_on_s", seconds(s.compression_based_on_s)},
                             {"peak_n", round_to(s.compression_peak_n, 0.1)},
                             {"mean_n", round_to(s.compression_mean_n, 0.1)},
                             {"action_limit_n", s.action_limit_n},
                             {"above_action_limit_s", seconds(s.above_action_limit_s)},
                             {"cumulative_n_s", round_to(s.cumulative_n_s, 0.1)}};
  return j;
}

std::string encode_summary(const ExposureSummary& s, const SummaryLabels& labels) { return to_json(s, labels).dump(); }

Result<LabelledSummary> decode_summary(std::string_view line, std::string_view where) {
  json j;
  try {
    j = json::parse(line);
  } catch (const json::parse_error& e) {
    return Error{fmt::format("{}: not JSON: {}", where, e.what())};
  }
  if (!j.is_object() || j.value("class", "") != "summary")
    return Error{fmt::format("{}: class: expected \"summary\"", where)};
  LabelledSummary out;
  ExposureSummary& s = out.summary;
  const std::string scope = j.value("scope", "");
  if (scope != "interval" && scope != "shift")
    return Error{fmt::format("{}: scope: expected \"interval\" or \"shift\"", where)};
  s.scope = scope == "shift" ? SummaryScope::Shift : SummaryScope::Interval;
  for (auto [key, field] : {std::pair{"start_ns", &s.start_ns}, std::pair{"end_ns", &s.end_ns}}) {
    if (!j.contains(key) || !j[key].is_number_integer()) return Error{fmt::format("{}: {}: expected an integer", where, key)};
    *field = j[key].get<std::int64_t>();
  }
  if (s.end_ns < s.start_ns) return Error{fmt::format("{}: end_ns: before start_ns", where)};
  s.partial = j.value("partial", false);
  std::vector<std::pair<const char*, double*>> numbers = {
      {"/coverage/tracked_s", &s.tracked_s},
      {"/coverage/init_s", &s.init_s},
      {"/coverage/lost_s", &s.lost_s},
      {"/coverage/empty_s", &s.empty_s},
      {"/coverage/gap_s", &s.gap_s},
      {"/trunk_inclination/mean_deg", &s.inclination_mean_deg},
      {"/trunk_inclination/min_deg", &s.inclination_min_deg},
      {"/trunk_inclination/max_deg", &s.inclination_max_deg},
      {"/lateral_bend/limit_deg", &s.bend_twist_limit_deg},
      {"/lateral_bend/over_s", &s.lateral_bend.over_s},
      {"/axial_twist/over_s", &s.axial_twist.over_s},
      {"/holding/limit_s", &s.hold_limit_s},
      {"/holding/beyond_s", &s.hold_beyond_s},
      {"/holding/longest_s", &s.longest_hold_s},
      {"/lumbar_compression/based_on_s", &s.compression_based_on_s},
      {"/lumbar_compression/peak_n", &s.compression_peak_n},
      {"/lumbar_compression/mean_n", &s.compression_mean_n},
      {"/lumbar_compression/action_limit_n", &s.action_limit_n},
      {"/lumbar_compression/above_action_limit_s", &s.above_action_limit_s},
      {"/lumbar_compression/cumulative_n_s", &s.cumulative_n_s}};
  // Optional: summaries written before it was counted have none.
  if (const json::json_pointer p("/axial_twist/unresolved_s"); j.contains(p)) {
    if (!j.at(p).is_number() || j.at(p).get<double>() < 0)
      return Error{fmt::format("{}: axial_twist/unresolved_s: expected a number of seconds", where)};
    s.twist_unresolved_s = j.at(p).get<double>();
  }
  std::vector<std::string> zone_paths;
  for (std::size_t z = 0; z < kInclinationZoneCount; ++z)
    zone_paths.push_back("/trunk_inclination/zones_s/" + std::string(zone_key(InclinationZone(z))));
  for (std::size_t z = 0; z < kInclinationZoneCount; ++z) numbers.emplace_back(zone_paths[z].c_str(), &s.zone_s[z]);
  for (auto [path, field] : numbers) {
    const json::json_pointer p(path);
    if (!j.contains(p) || !j.at(p).is_number())
      return Error{fmt::format("{}: {}: expected a number", where, std::string(path).substr(1))};
    *field = j.at(p).get<double>();
  }
  std::vector<std::pair<const char*, std::uint32_t*>> counts = {{"/lateral_bend/entries", &s.lateral_bend.entries},
                                                                {"/axial_twist/entries", &s.axial_twist.entries},
                                                                {"/holding/holds_beyond", &s.holds_beyond}};
  for (auto [path, field] : counts) {
    const json::json_pointer p(path);
    if (!j.contains(p) || !j.at(p).is_number_unsigned())
      return Error{fmt::format("{}: {}: expected a count", where, std::string(path).substr(1))};
    *field = j.at(p).get<std::uint32_t>();
  }
  auto read_array = [&](const char* key, auto& a) -> Status {
    if (!j.contains(key) || !j[key].is_array() || j[key].size() != a.size())
      return Error{fmt::format("{}: {}: expected {} numbers", where, key, a.size())};
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!j[key][i].is_number()) return Error{fmt::format("{}: {}[{}]: not a number", where, key, i)};
      a[i] = j[key][i].get<double>();
    }
    return Ok{};
  };
  if (auto st = read_array("reba_trunk_s", s.reba_trunk_s); !st) return st.error();
  if (auto st = read_array("rula_trunk_s", s.rula_trunk_s); !st) return st.error();
  if (j.contains("station") && j["station"].is_string()) out.labels.station = j["station"].get<std::string>();
  if (j.contains("worker") && j["worker"].is_string()) out.labels.worker = j["worker"].get<std::string>();
  if (j.contains("utc_start")) {
    if (!j["utc_start"].is_string()) return Error{fmt::format("{}: utc_start: expected a string", where)};
    auto t = parse_utc(j["utc_start"].get<std::string>());
    if (!t) return Error{fmt::format("{}: utc_start: {}", where, t.error().message)};
    out.labels.utc_offset_ns = *t - s.start_ns;
  }
  return out;
}

}  // namespace spinewatch
