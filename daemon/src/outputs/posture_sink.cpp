#include "support/note_level.hpp"

namespace spinewatch {

std::string_view to_string(NoteLevel level) {
  switch (level) {
    case NoteLevel::Info: return "info";
    case NoteLevel::Warning: return "warning";
    case NoteLevel::Error: return "error";
  }
  return "info";
}

}  // namespace spinewatch
