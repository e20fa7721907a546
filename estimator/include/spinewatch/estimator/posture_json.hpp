#pragma once
// The NDJSON posture stream, schema version 1 (docs/interfaces.md §3;
// docs/posture.schema.json). Encoding is one line without the newline.
#include <cstddef>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

inline constexpr int kPostureSchemaVersion = 1;

nlohmann::ordered_json to_json(const Posture& posture);
std::string encode_posture(const Posture& posture);
// Reads a posture line (ground truth, a recorded stream). `where` prefixes
// error messages, e.g. "ground_truth.ndjson:12".
Result<Posture> decode_posture(std::string_view line, std::string_view where);
Result<Posture> posture_from_json(const nlohmann::json& j, std::string_view where);

// A whole posture stream (a recorded stream, a recording's ground truth):
// one posture per line, blank lines and the stream's `hello` line skipped.
// An error names `source` and the line ("file:12: …"); a summaries file
// given where postures were meant is named as such.
struct NumberedPosture {
  std::size_t line = 0;  // 1-based, in the stream
  Posture posture;
};
Result<std::vector<NumberedPosture>> decode_posture_stream(std::istream& in, std::string_view source);

}  // namespace spinewatch
