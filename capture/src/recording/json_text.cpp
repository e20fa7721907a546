#include "spinewatch/capture/json_text.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace spinewatch {
namespace {

// nlohmann's text: "[json.exception.parse_error.101] parse error at line 3, column 5: …"
std::string_view without_id(std::string_view what) {
  if (auto p = what.find("] "); p != std::string_view::npos) what.remove_prefix(p + 2);
  return what;
}

// The line of the first occurrence of the quoted token in `what` (1-based), 0 if not found.
std::size_t line_of_token(std::string_view what, const std::string& text) {
  const auto open = what.find('\'');
  const auto close = what.rfind('\'');
  if (open == std::string_view::npos || close <= open + 1) return 0;
  const auto at = text.find(what.substr(open + 1, close - open - 1));
  if (at == std::string::npos) return 0;
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

}  // namespace

Result<nlohmann::json> parse_json_text(const std::string& text) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    std::string_view what = without_id(e.what());
    if (what.rfind("parse error at ", 0) == 0) what.remove_prefix(15);
    return Error{std::string(what)};
  } catch (const nlohmann::json::exception& e) {
    // Out of range (406: a number beyond double), the one other exception
    // parsing throws: no position of its own.
    const std::string_view what = without_id(e.what());
    if (const std::size_t line = line_of_token(what, text)) return Error{fmt::format("line {}: {}", line, what)};
    return Error{std::string(what)};
  }
}

}  // namespace spinewatch
