#include "spinewatch/daemon/config.hpp"

#include <algorithm>
#include <optional>
#include <set>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "support/mqtt_url.hpp"
#include "spinewatch/frames/printable.hpp"
#include "spinewatch/frames/text_file.hpp"
#include "support/nearest_name.hpp"

namespace spinewatch {
namespace {

std::string type_name(const toml::node& n) {
  return std::string(toml::impl::node_type_friendly_names[static_cast<int>(n.type())]);
}

// The node's value for `key`, of the key's type and within its range, or
// the problem ("expected an integer, got string", "500 is out of range [1, 120]").
Result<OptionValue> read_value(const OptionKey<Config>& key, const toml::node& n) {
  switch (key.type) {
    case OptionType::Integer: {
      auto v = n.value_exact<long long>();
      if (!n.is_integer() || !v) return Error{fmt::format("expected an integer, got {}", type_name(n))};
      const auto [min, max] = key.integer_range;
      if (*v < min || *v > max) return Error{fmt::format("{} is out of range [{}, {}]", *v, min, max)};
      return OptionValue(*v);
    }
    case OptionType::Number: {
      if (!n.is_number()) return Error{fmt::format("expected a number, got {}", type_name(n))};
      const double v = *n.value<double>();
      const auto [min, max] = key.number_range;
      if (key.zero_is_unknown && v != 0 && !(v >= min && v <= max))
        return Error{fmt::format("{} is out of range [{}, {}] (0 = not known)", v, min, max)};
      if (!key.zero_is_unknown && !(v >= min && v <= max))
        return Error{fmt::format("{} is out of range [{}, {}]", v, min, max)};
      return OptionValue(v);
    }
    case OptionType::Flag:
      if (!n.is_boolean()) return Error{fmt::format("expected true or false, got {}", type_name(n))};
      return OptionValue(*n.value<bool>());
    case OptionType::Text:
    case OptionType::Mode: {
      if (!n.is_string()) return Error{fmt::format("expected a string, got {}", type_name(n))};
      std::string v = *n.value<std::string>();
      if (!key.names.empty() && std::find(key.names.begin(), key.names.end(), v) == key.names.end())
        return Error{fmt::format("\"{}\" is not one of: {}", printable(v), fmt::join(key.names, ", "))};
      if (key.check_text)
        if (auto problem = key.check_text(v)) return Error{*problem};
      return OptionValue(std::move(v));
    }
  }
  return Error{"unknown key type"};
}

}  // namespace

std::string_view to_string(CameraSource source) {
  switch (source) {
    case CameraSource::Auto: return "auto";
    case CameraSource::V4l2: return "v4l2";
    case CameraSource::Libcamera: return "libcamera";
    case CameraSource::Recording: return "recording";
  }
  return "?";
}

std::string_view to_string(ReplayPace pace) { return pace == ReplayPace::Fast ? "fast" : "paced"; }

std::string_view to_string(AlertSignalMode mode) { return mode == AlertSignalMode::Pulse ? "pulse" : "steady"; }

namespace {

const OptionKey<Config>* find_key(const std::string& name) {
  for (const auto& k : config_table())
    if (k.name == name) return &k;
  return nullptr;
}

bool known_section(std::string_view section) {
  for (const auto& k : config_table())
    if (std::string_view(k.name).substr(0, k.name.find('.')) == section) return true;
  return false;
}

std::string at(std::string_view source, const toml::node& n) {
  return fmt::format("{}:{}", source, n.source().begin.line);
}

// The [mqtt] keys taken together: the key at fault and the problem.
std::optional<std::pair<std::string, std::string>> check_mqtt(const Config::Mqtt& m) {
  const auto url = parse_mqtt_url(m.url);  // "" (off) is no URL
  const bool tls = url && url->tls;
  for (const auto& [key, value] : {std::pair{"ca_file", &m.ca_file}, {"cert_file", &m.cert_file}, {"key_file", &m.key_file}})
    if (!value->empty() && !tls) return std::pair{key, "set, but mqtt.url is not mqtts://: a plain connection has no TLS"};
  if (m.cert_file.empty() != m.key_file.empty())
    return std::pair{m.cert_file.empty() ? "key_file" : "cert_file", "the client certificate and its key go together: give both"};
  if (!m.password_file.empty() && m.username.empty())
    return std::pair{"password_file", "set without mqtt.username"};
  if (m.reconnect_min_s > m.reconnect_max_s)
    return std::pair{"reconnect_min_s", fmt::format("{} is above mqtt.reconnect_max_s ({})", m.reconnect_min_s, m.reconnect_max_s)};
  return std::nullopt;
}

}  // namespace

std::vector<std::string> config_keys() {
  std::vector<std::string> names;
  for (const auto& k : config_table()) names.push_back(k.name);
  return names;
}

namespace {

std::vector<std::string> config_sections() {
  std::vector<std::string> sections;
  for (const std::string& key : config_keys()) {
    std::string section = key.substr(0, key.find('.'));
    if (std::find(sections.begin(), sections.end(), section) == sections.end()) sections.push_back(std::move(section));
  }
  return sections;
}

// "; did you mean X?" for a mistyped name near a known one (a typo of the
// key's own name, after its section), else nothing.
std::string did_you_mean(std::string_view typed, const std::vector<std::string>& known, std::string_view open = "",
                         std::string_view close = "") {
  const std::string_view own = typed.substr(typed.rfind('.') + 1);
  const auto nearest = nearest_name(typed, known, typo_allowance(own));
  return nearest ? fmt::format("; did you mean {}{}{}?", open, *nearest, close) : std::string();
}

}  // namespace

// Keys renamed since they were released, with their new names.
constexpr std::pair<std::string_view, std::string_view> kRenamedKeys[] = {
    {"cvsm.refine_sweeps", "cvsm.refine_steps"},  // Gauss–Newton steps replaced the sweeps
};

Result<Config> parse_config(std::string_view text, std::string_view source) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    // toml++ quotes the character it stopped at, a line end included.
    return Error{fmt::format("{}:{}: {}", source, e.source().begin.line, printable(e.description()))};
  }
  Config config;
  for (const auto& [section_key, section] : root) {
    const std::string section_name = printable(section_key.str());  // a quoted key may hold anything
    if (!section.is_table()) {
      if (known_section(section_name))
        return Error{fmt::format("{}: {}: expected a table [{}]", at(source, section), section_name, section_name)};
      return Error{fmt::format("{}: {}: unknown key", at(source, section), section_name)};
    }
    if (!known_section(section_name))
      return Error{fmt::format("{}: [{}]: unknown section{}", at(source, section), section_name,
                               did_you_mean(section_name, config_sections(), "[", "]"))};
    for (const auto& [key, value] : *section.as_table()) {
      const std::string name = section_name + "." + printable(key.str());
      const OptionKey<Config>* k = find_key(name);
      if (!k) {
        // A key a release renamed: the message says what to write instead.
        for (const auto& [was, now] : kRenamedKeys)
          if (name == was) return Error{fmt::format("{}: {}: unknown key; it is now {}", at(source, value), name, now)};
        return Error{fmt::format("{}: {}: unknown key{}", at(source, value), name, did_you_mean(name, config_keys()))};
      }
      auto v = read_value(*k, value);
      if (!v) return Error{fmt::format("{}: {}: {}", at(source, value), name, v.error().message)};
      k->set(config, *v);
    }
  }
  // The worker's values taken together (the landmarks below the stature,
  // the crest below C7): an error at the key the check names.
  if (const WorkerCheck check = check_known_worker(known_worker(config.subject)); !check.ok) {
    const std::string key = check.message.substr(0, check.message.find(':'));
    const toml::node* node = root["subject"][key].node();
    return Error{node ? fmt::format("{}: subject.{}", at(source, *node), check.message)
                      : fmt::format("{}: subject.{}", source, check.message)};
  }
  if (auto problem = check_mqtt(config.mqtt)) {
    const toml::node* node = root["mqtt"][problem->first].node();
    return Error{node ? fmt::format("{}: mqtt.{}: {}", at(source, *node), problem->first, problem->second)
                      : fmt::format("{}: mqtt.{}: {}", source, problem->first, problem->second)};
  }
  return config;
}

Result<Config> load_config(const std::filesystem::path& path) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  return parse_config(*text, path.string());
}

}  // namespace spinewatch
