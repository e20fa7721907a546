#pragma once
// The population sweep's tables: one row per run, then the pooled figures
// and the signed per-level bias (Markdown, as docs/anthropometry.md holds them).
#include <string>
#include <vector>

#include "spinewatch/population/sweep.hpp"

namespace spinewatch::population {

std::string format_runs(const std::vector<Run>& runs);
std::string format_pooled(const Pooled& pooled, std::string_view title);

}  // namespace spinewatch::population
