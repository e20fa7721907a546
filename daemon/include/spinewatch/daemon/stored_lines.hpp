#pragma once
// What the station's database holds, read back (docs/storage.md): for the
// CLI's `spinewatch report --db` and `spinewatch export --db`. The writer,
// Store, is the daemon's own (daemon/src/storage/).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// The interval summary lines of a database, oldest first (spinewatch
// report --db). Opened read-only; errors name the file.
Result<std::vector<std::string>> read_stored_summary_lines(const std::filesystem::path& path);

// The stored posture lines (every storage.posture_every-th), oldest first,
// with the wall-clock time each was stored (spinewatch export --db).
struct StoredLine {
  std::int64_t stored_ns = 0;  // CLOCK_REALTIME when the writer took it
  std::string line;
};
Result<std::vector<StoredLine>> read_stored_posture_lines(const std::filesystem::path& path);

}  // namespace spinewatch
