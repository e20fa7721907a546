#pragma once
// Text from an input quoted in an error message, with control characters
// escaped ("\n", "\t", "\x1b"): a message stays one line in the log
// whatever the input held.
#include <string>
#include <string_view>

namespace spinewatch {

std::string printable(std::string_view text);

}  // namespace spinewatch
