#include "spinewatch/estimator/load/alert_json.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "spinewatch/estimator/posture_json.hpp"

namespace spinewatch {

std::string encode_alert(const AlertEvent& e, const SummaryLabels& labels, bool silent) {
  auto round2 = [](double v) { return std::round(v * 100) / 100; };
  nlohmann::ordered_json j = {{"class", "alert"},
                              {"v", kPostureSchemaVersion},
                              {"rule", e.rule},
                              {"event", std::string(to_string(e.change))},
                              {"seq", e.seq},
                              {"t_ns", e.t_ns}};
  if (labels.utc_offset_ns) j["utc"] = format_utc(e.t_ns + *labels.utc_offset_ns);
  if (labels.station) j["station"] = *labels.station;
  if (labels.worker) j["worker"] = *labels.worker;
  j["held_s"] = std::round(e.held_s * 1000) / 1000;
  nlohmann::ordered_json values = nlohmann::ordered_json::object();
  if (e.inclination_deg) values["trunk_inclination_deg"] = round2(*e.inclination_deg);
  if (e.twist_deg) values["twist_deg"] = round2(*e.twist_deg);
  if (e.lateral_deg) values["lateral_bend_deg"] = round2(*e.lateral_deg);
  if (e.compression_n) values["l5_compression_n"] = std::round(*e.compression_n * 10) / 10;
  j["values"] = values;
  if (silent) j["silent"] = true;
  return j.dump();
}

}  // namespace spinewatch
