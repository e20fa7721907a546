// The annotated configuration (config/spinewatch.toml, `spinewatchd
// --print-config`) checked against the key tables: written by hand for the
// operator, it must still say exactly what the loader knows.
#include <fmt/format.h>
#include <toml++/toml.h>

#include "spinewatch/daemon/config.hpp"
#include "spinewatch/frames/printable.hpp"

namespace spinewatch {

std::string toml_text(const OptionValue& value) {
  if (const auto* i = std::get_if<long long>(&value)) return fmt::format("{}", *i);
  if (const auto* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  if (const auto* s = std::get_if<std::string>(&value)) return fmt::format("\"{}\"", printable(*s));
  std::string number = fmt::format("{}", std::get<double>(value));
  // A float as TOML writes one: "30.0", not the integer "30".
  if (number.find_first_of(".eEn") == std::string::npos) number += ".0";
  return number;
}

std::vector<std::string> annotated_config_problems(std::string_view text, std::string_view source) {
  auto config = parse_config(text, source);
  if (!config) return {config.error().message};  // a syntax error, an unknown key, a value out of range
  const toml::table root = toml::parse(text, source);
  std::vector<std::string> problems;
  for (const OptionKey<Config>& key : config_table()) {
    const auto dot = key.name.find('.');
    const toml::node* node = root[key.name.substr(0, dot)][key.name.substr(dot + 1)].node();
    if (!node) {
      problems.push_back(fmt::format("{}: {}: not listed; the file lists every key with its default ({})", source,
                                     key.name, toml_text(key.default_value())));
      continue;
    }
    const OptionValue given = key.get(*config), fallback = key.default_value();
    if (given != fallback)
      problems.push_back(fmt::format("{}:{}: {}: {} here, but the key's default is {}", source,
                                     node->source().begin.line, key.name, toml_text(given), toml_text(fallback)));
  }
  return problems;
}

}  // namespace spinewatch
