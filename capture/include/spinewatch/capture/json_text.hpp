#pragma once
// A JSON document from a file's text, with every way it can be malformed
// turned into one message that says where (nlohmann's parse errors carry
// the line; a number out of range, such as 1e309, does not, so its line is
// found from the token). Shared by the readers of recording.json and of
// phantom subject files.
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// Error messages are "line L, column C: …" or "line L: number overflow
// parsing '1e309'"; the caller prefixes the file.
Result<nlohmann::json> parse_json_text(const std::string& text);

}  // namespace spinewatch
