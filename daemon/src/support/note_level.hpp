#pragma once
// How much a note of the station's own (started, reload applied, stopped,
// an output that could not be opened) matters; the store's events.level.
#include <string_view>

namespace spinewatch {

enum class NoteLevel { Info, Warning, Error };
std::string_view to_string(NoteLevel level);  // "info", "warning", "error"

}  // namespace spinewatch
