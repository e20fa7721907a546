#pragma once
// What SIGHUP can change in a running daemon, and what needs a restart.
#include <string>
#include <vector>

#include "spinewatch/daemon/config.hpp"

namespace spinewatch {

// Keys ("section.key") whose values differ between two configurations.
std::vector<std::string> changed_keys(const Config& before, const Config& after);
// Keys that a reload applies without a restart (Reload::Live in their table).
bool reloadable_key(const std::string& key);
// Every key changed_keys() compares: all of config_keys().
std::vector<std::string> compared_keys();

}  // namespace spinewatch
