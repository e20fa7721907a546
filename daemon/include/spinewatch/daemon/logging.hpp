#pragma once
#include <string_view>

namespace spinewatch {

// Logs to standard error. Under systemd (JOURNAL_STREAM set) lines carry no
// timestamp, since the journal adds its own; on a terminal they do.
void setup_logging(std::string_view level = "info");
bool running_under_journal();

}  // namespace spinewatch
