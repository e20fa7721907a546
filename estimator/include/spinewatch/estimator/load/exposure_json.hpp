#pragma once
// "class": "summary" lines of the stream (docs/protocol.md,
// docs/summary.schema.json): one ExposureSummary each, plus what the
// caller knows of where and when (the estimator knows neither).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "spinewatch/estimator/load/exposure_summary.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct SummaryLabels {
  std::optional<std::string> station;
  std::optional<std::string> worker;  // the worker id a client gave (set_worker "id")
  // CLOCK_REALTIME − the stream's clock: gives "utc_start" / "utc_end".
  std::optional<std::int64_t> utc_offset_ns;
};

struct LabelledSummary {
  ExposureSummary summary;
  SummaryLabels labels;
  std::optional<std::int64_t> utc_start_ns() const {
    return labels.utc_offset_ns ? std::optional(summary.start_ns + *labels.utc_offset_ns) : std::nullopt;
  }
};

nlohmann::ordered_json to_json(const ExposureSummary& summary, const SummaryLabels& labels = {});
std::string encode_summary(const ExposureSummary& summary, const SummaryLabels& labels = {});
// `where` prefixes error messages, e.g. "shift.ndjson:12".
Result<LabelledSummary> decode_summary(std::string_view line, std::string_view where);

// "2026-12-02T07:55:00.000Z" and back (UTC; fractional seconds optional on input).
std::string format_utc(std::int64_t unix_ns);
Result<std::int64_t> parse_utc(std::string_view text);

}  // namespace spinewatch
