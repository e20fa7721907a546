#include "ops/config_reload.hpp"

namespace spinewatch {

// Both walk the configuration's key tables: a key compared is a key the
// loader reads, and whether a reload applies it is said in its table entry.

std::vector<std::string> changed_keys(const Config& before, const Config& after) {
  std::vector<std::string> changed;
  for (const auto& key : config_table())
    if (key.get(before) != key.get(after)) changed.push_back(key.name);
  return changed;
}

bool reloadable_key(const std::string& name) {
  for (const auto& key : config_table())
    if (key.name == name) return key.reload == Reload::Live;
  return false;
}

std::vector<std::string> compared_keys() { return config_keys(); }

}  // namespace spinewatch
