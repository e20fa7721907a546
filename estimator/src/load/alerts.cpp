#include "spinewatch/estimator/load/alerts.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

#include "common/toml_fields.hpp"

namespace spinewatch {
namespace {

struct Values {
  double inclination = 0, twist = 0, lateral = 0;
  std::optional<double> compression;
};

std::optional<Values> values_of(const Posture& p) {
  if (p.state != TrackingState::Tracking || !p.ergonomics) return std::nullopt;
  Values v{p.ergonomics->trunk_inclination_deg, p.ergonomics->twist_deg, p.ergonomics->lateral_bend_deg, std::nullopt};
  for (const LevelLoad& l : p.loads)
    if (l.level == kVertebraNames[kWaistIndex]) v.compression = l.compression_n;
  return v;
}

// Every condition the rule names, each threshold lowered by `relax`.
bool meets(const AlertRule& r, const Values& v, double relax_deg, double relax_n) {
  if (r.inclination_above_deg && !(v.inclination > *r.inclination_above_deg - relax_deg)) return false;
  if (r.twist_above_deg && !(std::abs(v.twist) > *r.twist_above_deg - relax_deg)) return false;
  if (r.lateral_above_deg && !(std::abs(v.lateral) > *r.lateral_above_deg - relax_deg)) return false;
  if (r.compression_above_n && !(v.compression && *v.compression > *r.compression_above_n - relax_n)) return false;
  return true;
}

AlertEvent event_of(const AlertRule& r, AlertChange change, const Posture& p, const Values& v, double held_s) {
  AlertEvent e{r.name, change, p.seq, p.t_ns, held_s, {}, {}, {}, {}};
  if (r.inclination_above_deg) e.inclination_deg = v.inclination;
  if (r.twist_above_deg) e.twist_deg = v.twist;
  if (r.lateral_above_deg) e.lateral_deg = v.lateral;
  if (r.compression_above_n) e.compression_n = v.compression;
  return e;
}

Result<AlertRule> parse_rule(const toml::table& t, std::string_view source, std::size_t index) {
  const std::string context = fmt::format("rule[{}]", index);
  const auto line = t.source().begin.line;
  AlertRule r;
  static const std::set<std::string_view> known = {"name", "inclination_above_deg", "twist_above_deg",
                                                   "lateral_above_deg", "compression_above_n", "hold_s",
                                                   "hysteresis_deg", "hysteresis_n", "min_interval_s"};
  for (const auto& [key, node] : t)
    if (!known.count(key.str()))
      return Error{fmt::format("{}:{}: {}.{}: unknown key", source, node.source().begin.line, context, key.str())};
  const auto name = t["name"].value<std::string>();
  if (!name || name->empty()) return Error{fmt::format("{}:{}: {}.name: missing (a non-empty string)", source, line, context)};
  r.name = *name;
  struct Optional {
    const char* key;
    std::optional<double>* out;
    double max;
  };
  for (const Optional& o : {Optional{"inclination_above_deg", &r.inclination_above_deg, 180},
                            Optional{"twist_above_deg", &r.twist_above_deg, 180},
                            Optional{"lateral_above_deg", &r.lateral_above_deg, 180},
                            Optional{"compression_above_n", &r.compression_above_n, 1e5}}) {
    if (!t.contains(o.key)) continue;
    auto v = detail::toml_number(t, o.key, source, context, o.key == std::string_view("inclination_above_deg") ? -90 : 0, o.max);
    if (!v) return v.error();
    *o.out = *v;
  }
  if (!r.inclination_above_deg && !r.twist_above_deg && !r.lateral_above_deg && !r.compression_above_n)
    return Error{fmt::format("{}:{}: {}: names no condition (inclination_above_deg, twist_above_deg, "
                             "lateral_above_deg or compression_above_n)", source, line, context)};
  for (auto [key, out, max] : {std::tuple{"hold_s", &r.hold_s, 86400.0}, std::tuple{"hysteresis_deg", &r.hysteresis_deg, 90.0},
                               std::tuple{"hysteresis_n", &r.hysteresis_n, 1e5},
                               std::tuple{"min_interval_s", &r.min_interval_s, 86400.0}}) {
    if (!t.contains(key)) continue;
    auto v = detail::toml_number(t, key, source, context, 0, max);
    if (!v) return v.error();
    *out = *v;
  }
  return r;
}

}  // namespace

std::string_view to_string(AlertChange change) { return change == AlertChange::Raised ? "raised" : "cleared"; }

Result<std::vector<AlertRule>> parse_alert_rules(std::string_view text, std::string_view source) {
  auto root = detail::parse_toml(text, source);
  if (!root) return root.error();
  for (const auto& [key, node] : *root)
    if (key.str() != "rule")
      return Error{fmt::format("{}:{}: {}: unknown key (rules are [[rule]] tables)", source, node.source().begin.line, key.str())};
  std::vector<AlertRule> rules;
  const toml::node* rule_node = root->get("rule");
  if (!rule_node) return rules;
  const toml::array* list = rule_node->as_array();
  if (!list || !list->is_array_of_tables())
    return Error{fmt::format("{}:{}: rule: expected [[rule]] tables", source, rule_node->source().begin.line)};
  std::set<std::string> names;
  for (std::size_t i = 0; i < list->size(); ++i) {
    auto r = parse_rule(*list->get(i)->as_table(), source, i);
    if (!r) return r.error();
    if (!names.insert(r->name).second)
      return Error{fmt::format("{}:{}: rule[{}].name: \"{}\" is used twice", source,
                               list->get(i)->source().begin.line, i, r->name)};
    rules.push_back(std::move(r).value());
  }
  return rules;
}

const std::vector<AlertRule>& builtin_alert_rules() {
  static const std::vector<AlertRule> rules = [] {
    auto parsed = parse_alert_rules(builtin_alerts_toml(), "config/alerts.toml");
    if (!parsed) throw std::logic_error(parsed.error().message);  // the embedded file is tested
    return std::move(parsed).value();
  }();
  return rules;
}

AlertMonitor::AlertMonitor(std::vector<AlertRule> rules) : rules_(std::move(rules)), states_(rules_.size()) {}

std::vector<AlertEvent> AlertMonitor::update(const Posture& p) {
  std::vector<AlertEvent> out;
  const std::optional<Values> v = values_of(p);
  if (!v) {
    // Not tracked: nothing is known. A raised alert stays up; a run of
    // postures towards raising one is broken.
    for (State& s : states_) s.holding_since_ns.reset();
    return out;
  }
  for (std::size_t i = 0; i < rules_.size(); ++i) {
    const AlertRule& r = rules_[i];
    State& s = states_[i];
    if (s.raised_at_ns) {
      if (!meets(r, *v, r.hysteresis_deg, r.hysteresis_n)) {
        out.push_back(event_of(r, AlertChange::Cleared, p, *v, double(p.t_ns - *s.raised_at_ns) * 1e-9));
        s.raised_at_ns.reset();
        s.holding_since_ns.reset();
      }
      continue;
    }
    if (!meets(r, *v, 0, 0)) {
      s.holding_since_ns.reset();
      continue;
    }
    if (!s.holding_since_ns) s.holding_since_ns = p.t_ns;
    const double held_s = double(p.t_ns - *s.holding_since_ns) * 1e-9;
    const bool rested = !s.last_raise_ns || double(p.t_ns - *s.last_raise_ns) * 1e-9 >= r.min_interval_s;
    if (held_s >= r.hold_s && rested) {
      out.push_back(event_of(r, AlertChange::Raised, p, *v, held_s));
      s.raised_at_ns = s.last_raise_ns = p.t_ns;
    }
  }
  return out;
}

}  // namespace spinewatch
