#pragma once
// A component's configuration keys, described once, beside the struct that
// holds their values: each key's name, type, range, whether a reload applies
// it, and the member it sets. The default is the member's initialiser (a key
// reads it from a default-constructed struct), so a key has one home.
//
// The table is plain data: no file format here. The daemon's loader reads
// TOML into it, its reload compares configurations through it, and a test
// checks the annotated configuration (config/spinewatch.toml) against it
// (docs/configuration.md, "Adding a key").
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace spinewatch {

enum class OptionType : std::uint8_t {
  Integer,  // an int in [integer_range]
  Number,   // a double in [number_range] (an integer is taken too)
  Flag,     // true or false
  Text,     // a string, one of `names` when they are given
  Mode,     // one of `names`, held as its enum
};

enum class Reload : std::uint8_t {
  Restart,  // a changed value waits for a restart
  Live,     // a reload (SIGHUP) applies it
};

// A key's value: Integer → long long, Number → double, Flag → bool,
// Text → the text, Mode → the mode's name.
using OptionValue = std::variant<long long, double, bool, std::string>;

template <class S>
struct OptionKey {
  std::string name;  // as written in the file, within its section
  OptionType type = OptionType::Text;
  std::pair<long long, long long> integer_range{0, 0};
  std::pair<double, double> number_range{0, 0};
  bool zero_is_unknown = false;  // Number: 0 (not known) or a value in the range
  std::vector<std::string> names;  // Mode: its names; Text: the values allowed (none: any)
  // Text: a check of its own (the problem, or nothing when the value is
  // fine), for a value with a grammar (a URL).
  std::function<std::optional<std::string>(const std::string&)> check_text;
  Reload reload = Reload::Restart;
  std::function<OptionValue(const S&)> get;
  std::function<void(S&, const OptionValue&)> set;  // a value of the key's type, checked

  OptionValue default_value() const { return get(S{}); }
  // Applied by a reload without a restart.
  OptionKey live() && {
    reload = Reload::Live;
    return std::move(*this);
  }
  OptionKey checked_by(std::function<std::optional<std::string>(const std::string&)> check) && {
    check_text = std::move(check);
    return std::move(*this);
  }
};

template <class S>
using OptionTable = std::vector<OptionKey<S>>;

template <class S>
OptionKey<S> integer_key(std::string name, int S::*member, long long min, long long max) {
  OptionKey<S> k;
  k.name = std::move(name);
  k.type = OptionType::Integer;
  k.integer_range = {min, max};
  k.get = [member](const S& s) { return OptionValue(static_cast<long long>(s.*member)); };
  k.set = [member](S& s, const OptionValue& v) { s.*member = static_cast<int>(std::get<long long>(v)); };
  return k;
}

template <class S>
OptionKey<S> number_key(std::string name, double S::*member, double min, double max) {
  OptionKey<S> k;
  k.name = std::move(name);
  k.type = OptionType::Number;
  k.number_range = {min, max};
  k.get = [member](const S& s) { return OptionValue(s.*member); };
  k.set = [member](S& s, const OptionValue& v) { s.*member = std::get<double>(v); };
  return k;
}

// A measurement that may not be known: 0, or a value in [min, max].
template <class S>
OptionKey<S> measurement_key(std::string name, double S::*member, double min, double max) {
  OptionKey<S> k = number_key(std::move(name), member, min, max);
  k.zero_is_unknown = true;
  return k;
}

template <class S>
OptionKey<S> flag_key(std::string name, bool S::*member) {
  OptionKey<S> k;
  k.name = std::move(name);
  k.type = OptionType::Flag;
  k.get = [member](const S& s) { return OptionValue(s.*member); };
  k.set = [member](S& s, const OptionValue& v) { s.*member = std::get<bool>(v); };
  return k;
}

template <class S>
OptionKey<S> text_key(std::string name, std::string S::*member, std::vector<std::string> allowed = {}) {
  OptionKey<S> k;
  k.name = std::move(name);
  k.type = OptionType::Text;
  k.names = std::move(allowed);
  k.get = [member](const S& s) { return OptionValue(s.*member); };
  k.set = [member](S& s, const OptionValue& v) { s.*member = std::get<std::string>(v); };
  return k;
}

// A mode: one of `modes`, held as its enum. The names here are the only
// place the text of a mode appears; code switches on E.
template <class S, class E>
OptionKey<S> mode_key(std::string name, E S::*member, std::vector<std::pair<std::string, E>> modes) {
  OptionKey<S> k;
  k.name = std::move(name);
  k.type = OptionType::Mode;
  for (const auto& mode : modes) k.names.push_back(mode.first);
  k.get = [member, modes](const S& s) {
    for (const auto& [text, value] : modes)
      if (value == s.*member) return OptionValue(text);
    return OptionValue(std::string("?"));  // a value no name spells: none of the table's
  };
  k.set = [member, modes](S& s, const OptionValue& v) {
    for (const auto& [text, value] : modes)
      if (text == std::get<std::string>(v)) s.*member = value;
  };
  return k;
}

// The keys of `table`, a section of the aggregate A at `section`, as keys of
// A named "section.key".
template <class A, class S>
void add_section(OptionTable<A>& into, const std::string& section_name, S A::*section, const OptionTable<S>& table) {
  for (const OptionKey<S>& key : table) {
    OptionKey<A> k;
    k.name = section_name + "." + key.name;
    k.type = key.type;
    k.integer_range = key.integer_range;
    k.number_range = key.number_range;
    k.zero_is_unknown = key.zero_is_unknown;
    k.names = key.names;
    k.check_text = key.check_text;
    k.reload = key.reload;
    k.get = [section, get = key.get](const A& a) { return get(a.*section); };
    k.set = [section, set = key.set](A& a, const OptionValue& v) { set(a.*section, v); };
    into.push_back(std::move(k));
  }
}

}  // namespace spinewatch
