#include "http/state_json.hpp"

#include <nlohmann/json.hpp>

#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/version.hpp"

namespace spinewatch {
namespace {

nlohmann::ordered_json view_json(const LiveSummary* s, int v) {
  if (!s) return {{"subject", "unknown"}, {"whole", false}, {"pixels", 0}, {"background", "unknown"}};
  const ViewCoverage& c = s->coverage[v];
  return {{"subject", c.describe()},
          {"whole", c.whole()},
          {"pixels", c.pixels},
          {"background", std::string(to_string(s->background[v]))}};
}

}  // namespace

std::string state_json(const StationInfo& station, const DaemonMetrics& m, const LiveSummary* latest,
                       std::int64_t now_ns) {
  using nlohmann::ordered_json;
  ordered_json j;
  j["class"] = "state";
  j["v"] = 1;
  j["station"] = station.station;
  j["daemon_version"] = kVersion;
  j["source"] = station.source;
  j["uptime_s"] = m.uptime_s;
  if (latest) {
    const Posture& p = latest->posture;
    j["state"] = std::string(to_string(p.state));
    j["seq"] = p.seq;
    j["fit_cost"] = p.fit.cost;
    j["fit_flag"] = p.fit.flag ? ordered_json(*p.fit.flag) : ordered_json(nullptr);
    j["age_s"] = static_cast<double>(std::max<std::int64_t>(0, now_ns - latest->taken_ns)) * 1e-9;
    j["posture"] = to_json(p);
  } else {
    for (const char* k : {"state", "seq", "fit_cost", "fit_flag", "age_s", "posture"}) j[k] = nullptr;
  }
  j["views"] = {{"frontal", view_json(latest, 0)}, {"lateral", view_json(latest, 1)}};
  j["calibration"] = {{"source", station.calibration}, {"default_rig", station.default_rig}};
  j["background"] = {{"mode", std::string(to_string(station.background_mode))}, {"relearn", station.relearn_available}};
  j["live"] = {{"fps", station.fps}, {"camera_pixels", station.camera_pixels}};
  const auto& p = m.pipeline;
  j["counters"] = {
      {"pairs", p.pairs},
      {"pairs_processed", p.pairs_processed},
      {"pairs_dropped", p.pairs_dropped},
      {"frames_frontal", p.source.camera[0].frames},
      {"frames_lateral", p.source.camera[1].frames},
      {"frames_lost", p.source.frames_lost},
      {"camera_restarts", p.source.camera[0].restarts + p.source.camera[1].restarts},
      {"postures_init", m.postures.by_state[0]},
      {"postures_tracking", m.postures.by_state[1]},
      {"postures_lost", m.postures.by_state[2]},
      {"tracking_lost", m.postures.tracking_lost},
      {"stream_clients", m.publisher.clients},
      {"stream_clients_dropped", m.publisher.clients_dropped},
      {"stream_lines_dropped", m.publisher.lines_dropped},
      {"http_connections", m.http.connections},
      {"http_dropped", m.http.rejected + m.http.timed_out + m.http.bad_requests},
      {"stream_viewers", m.http.stream_viewers},
      {"live_samples_dropped", m.live.samples_dropped},
  };
  if (m.truth)
    j["truth"] = {{"pairs", m.truth->pairs},
                  {"pairs_not_tracking", m.truth->pairs_not_tracking},
                  {"vertebrae_mean_mm", m.truth->vertebrae_mean_mm},
                  {"neck_mean_mm", m.truth->neck_mean_mm},
                  {"waist_mean_mm", m.truth->waist_mean_mm},
                  {"last_vertebrae_mm", m.truth->last_vertebrae_mm}};
  else
    j["truth"] = nullptr;
  j["rates"] = {{"pairs_per_s", m.pairs_per_s},
                {"latency_mean_ms", m.latency.count ? 1e3 * m.latency.sum_s / static_cast<double>(m.latency.count) : 0.0}};
  return j.dump();
}

}  // namespace spinewatch
