#pragma once
// "class": "alert" lines (docs/protocol.md, docs/alert.schema.json).
#include <optional>
#include <string>

#include "spinewatch/estimator/load/alerts.hpp"
#include "spinewatch/estimator/load/exposure_json.hpp"

namespace spinewatch {

// labels as for summaries: station, worker, utc_offset_ns (gives "utc").
// silent: the station records the alert without signalling it ([alerts]
// silent); the line then says "silent": true.
std::string encode_alert(const AlertEvent& event, const SummaryLabels& labels = {}, bool silent = false);

}  // namespace spinewatch
