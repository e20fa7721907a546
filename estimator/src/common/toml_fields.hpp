#pragma once
// Reading checked numbers from a TOML table with "FILE:LINE: table.key: problem" errors.
#include <string>
#include <string_view>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::detail {

// "FILE:LINE" of a node, the start of every message about it.
inline std::string toml_where(std::string_view source, const toml::node& n) {
  return fmt::format("{}:{}", source, n.source().begin.line);
}

inline Result<double> toml_number(const toml::table& table, std::string_view key, std::string_view source,
                                  std::string_view context, double min, double max) {
  const toml::node* n = table.get(key);
  if (!n) return Error{fmt::format("{}:{}: {}.{}: missing", source, table.source().begin.line, context, key)};
  if (!n->is_number())
    return Error{fmt::format("{}:{}: {}.{}: expected a number", source, n->source().begin.line, context, key)};
  const double v = *n->value<double>();
  if (!(v >= min && v <= max))
    return Error{fmt::format("{}:{}: {}.{}: {} is out of range [{}, {}]", source, n->source().begin.line, context,
                             key, v, min, max)};
  return v;
}

inline Result<toml::table> parse_toml(std::string_view text, std::string_view source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    return Error{fmt::format("{}:{}: {}", source, e.source().begin.line, e.description())};
  }
}

inline Result<const toml::table*> toml_table(const toml::table& root, std::string_view path, std::string_view source) {
  const toml::table* t = root.at_path(path).as_table();
  if (!t) return Error{fmt::format("{}: [{}]: missing", source, path)};
  return t;
}

struct NumberField {
  const char* key;
  double* out;
  double min, max;
};

inline Status read_numbers(const toml::table& table, std::string_view source, std::string_view context,
                           std::initializer_list<NumberField> fields) {
  for (const NumberField& f : fields) {
    auto v = toml_number(table, f.key, source, context, f.min, f.max);
    if (!v) return v.error();
    *f.out = *v;
  }
  return Ok{};
}

}  // namespace spinewatch::detail
