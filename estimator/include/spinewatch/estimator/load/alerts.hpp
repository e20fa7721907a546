#pragma once
// Alert rules on the posture stream (docs/exposure.md, "Alerts"): a rule
// raises when its conditions have held long enough, clears with
// hysteresis, and raises again no sooner than its minimum interval. Pure
// computation on postures; one monitor per stream, not thread-safe.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct AlertRule {
  std::string name;
  std::optional<double> inclination_above_deg, twist_above_deg, lateral_above_deg, compression_above_n;
  double hold_s = 0;
  double hysteresis_deg = 0, hysteresis_n = 0;
  double min_interval_s = 0;
};

// TOML [[rule]] tables (config/alerts.toml); errors name file, line and key.
Result<std::vector<AlertRule>> parse_alert_rules(std::string_view toml_text, std::string_view source);
std::string_view builtin_alerts_toml();  // config/alerts.toml, embedded
const std::vector<AlertRule>& builtin_alert_rules();

enum class AlertChange : std::uint8_t { Raised, Cleared };
std::string_view to_string(AlertChange change);

struct AlertEvent {
  std::string rule;
  AlertChange change = AlertChange::Raised;
  std::uint64_t seq = 0;
  std::int64_t t_ns = 0;
  double held_s = 0;  // raised: how long the conditions had held; cleared: how long the alert was up
  // The posture's values the rule looks at (those it names).
  std::optional<double> inclination_deg, twist_deg, lateral_deg, compression_n;
};

class AlertMonitor {
 public:
  explicit AlertMonitor(std::vector<AlertRule> rules);
  // What this posture raised or cleared (usually nothing).
  std::vector<AlertEvent> update(const Posture& posture);
  const std::vector<AlertRule>& rules() const { return rules_; }

 private:
  struct State {
    std::optional<std::int64_t> holding_since_ns;  // conditions met on every tracked posture since
    std::optional<std::int64_t> raised_at_ns;       // up since
    std::optional<std::int64_t> last_raise_ns;
  };
  std::vector<AlertRule> rules_;
  std::vector<State> states_;
};

}  // namespace spinewatch
