#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace spinewatch {

// log.level and the CLI's --log-level, parsed once.
enum class LogLevel : std::uint8_t { Trace, Debug, Info, Warn, Error };
// Each level's name as the configuration and --log-level spell it.
const std::vector<std::pair<std::string, LogLevel>>& log_level_names();

// Logs to standard error. Under systemd (JOURNAL_STREAM set) lines carry no
// timestamp, since the journal adds its own; on a terminal they do.
void setup_logging(LogLevel level = LogLevel::Info);
// The running logger's level (a reload).
void set_log_level(LogLevel level);
bool running_under_journal();

}  // namespace spinewatch
