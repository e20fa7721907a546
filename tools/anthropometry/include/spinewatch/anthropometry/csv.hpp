#pragma once
// A comma-separated table read by column name: a header line, then one
// record per line. Fields may be quoted ("a, b" with "" for a quote); a
// record does not span lines. CRLF and LF line ends both read.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::anthropometry {

class CsvTable {
 public:
  // `source` names the text in errors ("FILE:LINE: problem").
  static Result<CsvTable> parse(std::string_view text, std::string_view source);

  const std::vector<std::string>& header() const { return header_; }
  std::size_t rows() const { return rows_.size(); }
  // Index of a header column, or an error naming the file and the column.
  Result<std::size_t> column(std::string_view name) const;
  const std::string& field(std::size_t row, std::size_t column) const { return rows_[row].fields[column]; }
  int line(std::size_t row) const { return rows_[row].line; }  // 1-based, in the text
  std::string_view source() const { return source_; }

 private:
  struct Row {
    int line = 0;
    std::vector<std::string> fields;
  };
  std::string source_;
  std::vector<std::string> header_;
  std::vector<Row> rows_;
};

}  // namespace spinewatch::anthropometry
