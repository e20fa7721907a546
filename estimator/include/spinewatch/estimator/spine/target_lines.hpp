#pragma once
// The targets file of `spinewatch deform` (docs/interfaces.md §4): NDJSON, one
// object a line — "neck" and "waist" ([x, y, z] mm, T1 and L5 body
// centres), optionally "neck_dir"/"waist_dir" (unit vectors), "seq" and
// "t_ns". Parsed from text here; the CLI reads the file.
#include <cstdint>
#include <string_view>
#include <vector>

#include "spinewatch/estimator/spine/spine_dynamics.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct TargetLine {
  SpineTargets targets;
  std::uint64_t seq = 0;  // the line's index among the target lines when it has none
  std::int64_t t_ns = 0;
};

// One line; `where` prefixes messages ("targets.ndjson:3: neck: missing").
Result<TargetLine> parse_target_line(std::string_view text, std::string_view where, std::uint64_t index);

// Every line of a targets file's text, blank lines skipped; the first bad
// line is the error ("<name>:<line>: ..."), and a file without a target
// line is one too.
Result<std::vector<TargetLine>> parse_target_lines(std::string_view text, std::string_view name);

}  // namespace spinewatch
