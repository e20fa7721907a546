#pragma once
#include <filesystem>
#include <vector>

#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// Reads an NDJSON posture stream (replay output, ground_truth.ndjson, a
// captured daemon stream). Hello lines are skipped; any other bad line is
// an error naming FILE:LINE and the field.
Result<std::vector<Posture>> read_posture_file(const std::filesystem::path& path);

}  // namespace spinewatch
