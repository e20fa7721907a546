#include "spinewatch/daemon/exposure_options.hpp"

#include <fstream>
#include <sstream>

namespace spinewatch {

ExposureOptions exposure_options(const Config& config) {
  ExposureOptions o;
  o.interval_ns = std::int64_t(config.exposure.interval_s) * 1'000'000'000;
  return o;
}

Result<std::vector<AlertRule>> load_alert_rules(const Config& config) {
  if (!config.alerts.enabled) return std::vector<AlertRule>{};
  if (config.alerts.rules.empty()) return builtin_alert_rules();
  std::ifstream in(config.alerts.rules);
  if (!in) return Error{"alerts.rules: " + config.alerts.rules + ": cannot be read"};
  std::stringstream text;
  text << in.rdbuf();
  return parse_alert_rules(text.str(), config.alerts.rules);
}

}  // namespace spinewatch
