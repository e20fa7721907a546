#include "spinewatch/anthropometry/csv.hpp"

#include <fmt/format.h>

namespace spinewatch::anthropometry {
namespace {

// Splits one line into fields; an unterminated quote is an error.
Result<std::vector<std::string>> split_line(std::string_view line, std::string_view source, int number) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c != '"') {
        fields.back() += c;
      } else if (i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';  // "" inside quotes is one quote
        ++i;
      } else {
        quoted = false;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  if (quoted) return Error{fmt::format("{}:{}: a quoted field is not closed on its line", source, number)};
  return fields;
}

}  // namespace

Result<CsvTable> CsvTable::parse(std::string_view text, std::string_view source) {
  CsvTable table;
  table.source_ = std::string(source);
  int number = 0;
  bool have_header = false;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) continue;  // a trailing blank line is not a record
    auto fields = split_line(line, source, number);
    if (!fields) return fields.error();
    if (!have_header) {
      table.header_ = std::move(fields).value();
      have_header = true;
      continue;
    }
    if (fields->size() != table.header_.size())
      return Error{fmt::format("{}:{}: {} fields, the header has {}", source, number, fields->size(), table.header_.size())};
    table.rows_.push_back({number, std::move(fields).value()});
  }
  if (!have_header) return Error{fmt::format("{}: empty, expected a header line", source)};
  return table;
}

Result<std::size_t> CsvTable::column(std::string_view name) const {
  for (std::size_t i = 0; i < header_.size(); ++i)
    if (header_[i] == name) return i;
  return Error{fmt::format("{}:1: column {}: missing from the header", source_, name)};
}

}  // namespace spinewatch::anthropometry
