#include "spinewatch/daemon/config.hpp"

#include <algorithm>
#include <functional>
#include <optional>
#include <set>
#include <variant>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "spinewatch/daemon/mqtt_url.hpp"
#include "spinewatch/frames/printable.hpp"
#include "spinewatch/frames/text_file.hpp"
#include "nearest_name.hpp"

namespace spinewatch {
namespace {

using Setter = std::function<std::optional<std::string>(Config&, const toml::node&)>;

struct Key {
  std::string name;  // "section.key"
  Setter set;        // returns a problem, or nothing when the value was taken
};

template <class T>
struct Range {
  T min, max;
};

Key int_key(std::string name, int& (*field)(Config&), Range<long long> r) {
  return {std::move(name), [field, r](Config& c, const toml::node& n) -> std::optional<std::string> {
            auto v = n.value_exact<long long>();
            if (!n.is_integer() || !v) return fmt::format("expected an integer, got {}", toml::impl::node_type_friendly_names[static_cast<int>(n.type())]);
            if (*v < r.min || *v > r.max) return fmt::format("{} is out of range [{}, {}]", *v, r.min, r.max);
            field(c) = static_cast<int>(*v);
            return std::nullopt;
          }};
}

Key double_key(std::string name, double& (*field)(Config&), Range<double> r) {
  return {std::move(name), [field, r](Config& c, const toml::node& n) -> std::optional<std::string> {
            if (!n.is_number()) return fmt::format("expected a number, got {}", toml::impl::node_type_friendly_names[static_cast<int>(n.type())]);
            const double v = *n.value<double>();
            if (!(v >= r.min && v <= r.max)) return fmt::format("{} is out of range [{}, {}]", v, r.min, r.max);
            field(c) = v;
            return std::nullopt;
          }};
}

// 0 or a value in [min, max]: a measurement that may not be known.
Key optional_double_key(std::string name, double& (*field)(Config&), Range<double> r) {
  return {std::move(name), [field, r](Config& c, const toml::node& n) -> std::optional<std::string> {
            if (!n.is_number()) return fmt::format("expected a number, got {}", toml::impl::node_type_friendly_names[static_cast<int>(n.type())]);
            const double v = *n.value<double>();
            if (v != 0 && !(v >= r.min && v <= r.max))
              return fmt::format("{} is out of range [{}, {}] (0 = not known)", v, r.min, r.max);
            field(c) = v;
            return std::nullopt;
          }};
}

Key bool_key(std::string name, bool& (*field)(Config&)) {
  return {std::move(name), [field](Config& c, const toml::node& n) -> std::optional<std::string> {
            if (!n.is_boolean()) return fmt::format("expected true or false, got {}", toml::impl::node_type_friendly_names[static_cast<int>(n.type())]);
            field(c) = *n.value<bool>();
            return std::nullopt;
          }};
}

Key string_key(std::string name, std::string& (*field)(Config&), std::vector<std::string> allowed = {}) {
  return {std::move(name), [field, allowed](Config& c, const toml::node& n) -> std::optional<std::string> {
            if (!n.is_string()) return fmt::format("expected a string, got {}", toml::impl::node_type_friendly_names[static_cast<int>(n.type())]);
            std::string v = *n.value<std::string>();
            if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), v) == allowed.end())
              return fmt::format("\"{}\" is not one of: {}", printable(v), fmt::join(allowed, ", "));
            field(c) = std::move(v);
            return std::nullopt;
          }};
}

// mqtt.url: "" (off) or a URL parse_mqtt_url takes.
Key mqtt_url_key() {
  return {"mqtt.url", [](Config& c, const toml::node& n) -> std::optional<std::string> {
            if (!n.is_string()) return fmt::format("expected a string, got {}", toml::impl::node_type_friendly_names[static_cast<int>(n.type())]);
            std::string v = *n.value<std::string>();
            if (!v.empty())
              if (auto url = parse_mqtt_url(v); !url) return url.error().message;
            c.mqtt.url = std::move(v);
            return std::nullopt;
          }};
}

// A mode: one of `names`, stored as its enum. The names are the only place
// the text of a mode appears; everything after the loader switches on E.
template <class E>
Key enum_key(std::string name, E& (*field)(Config&), std::vector<std::pair<std::string, E>> names) {  // E given explicitly
  return {std::move(name), [field, names = std::move(names)](Config& c, const toml::node& n) -> std::optional<std::string> {
            if (!n.is_string()) return fmt::format("expected a string, got {}", toml::impl::node_type_friendly_names[static_cast<int>(n.type())]);
            const std::string v = *n.value<std::string>();
            std::vector<std::string_view> allowed;
            for (const auto& [text, value] : names) {
              if (text == v) {
                field(c) = value;
                return std::nullopt;
              }
              allowed.push_back(text);
            }
            return fmt::format("\"{}\" is not one of: {}", printable(v), fmt::join(allowed, ", "));
          }};
}

// The one table of keys. Add a key here and in config/spinewatch.toml.
const std::vector<Key>& keys() {
  static const std::vector<Key> table = {
      string_key("station.name", [](Config& c) -> std::string& { return c.station.name; }),

      enum_key<CameraSource>("cameras.source", [](Config& c) -> CameraSource& { return c.cameras.source; },
               {{"auto", CameraSource::Auto}, {"v4l2", CameraSource::V4l2}, {"libcamera", CameraSource::Libcamera},
                {"recording", CameraSource::Recording}}),
      // V4L2 device nodes, or libcamera camera ids when cameras.source = "libcamera".
      string_key("cameras.frontal", [](Config& c) -> std::string& { return c.cameras.frontal; }),
      string_key("cameras.lateral", [](Config& c) -> std::string& { return c.cameras.lateral; }),
      enum_key<PixelFormat>("cameras.pixel_format", [](Config& c) -> PixelFormat& { return c.cameras.pixel_format; },
               {{"YUYV", PixelFormat::YUYV}, {"GREY", PixelFormat::GREY}}),
      int_key("cameras.width", [](Config& c) -> int& { return c.cameras.width; }, {16, 4096}),
      int_key("cameras.height", [](Config& c) -> int& { return c.cameras.height; }, {16, 4096}),
      double_key("cameras.fps", [](Config& c) -> double& { return c.cameras.fps; }, {1.0, 120.0}),
      int_key("cameras.exposure_us", [](Config& c) -> int& { return c.cameras.exposure_us; }, {0, 1000000}),
      int_key("cameras.gain", [](Config& c) -> int& { return c.cameras.gain; }, {-1, 100000}),
      int_key("cameras.buffers", [](Config& c) -> int& { return c.cameras.buffers; }, {4, 32}),
      string_key("cameras.calibration", [](Config& c) -> std::string& { return c.cameras.calibration; }),
      string_key("cameras.recording", [](Config& c) -> std::string& { return c.cameras.recording; }),
      enum_key<ReplayPace>("cameras.replay", [](Config& c) -> ReplayPace& { return c.cameras.replay; },
               {{"paced", ReplayPace::Paced}, {"fast", ReplayPace::Fast}}),
      double_key("cameras.watchdog_s", [](Config& c) -> double& { return c.cameras.watchdog_s; }, {0.1, 60.0}),

      enum_key<sync::TriggerMode>("trigger.mode", [](Config& c) -> sync::TriggerMode& { return c.trigger.mode; },
               {{"free-run", sync::TriggerMode::FreeRun}, {"master", sync::TriggerMode::Master},
                {"slave", sync::TriggerMode::Slave}}),
      string_key("trigger.chip", [](Config& c) -> std::string& { return c.trigger.chip; }),
      int_key("trigger.line", [](Config& c) -> int& { return c.trigger.line; }, {0, 1023}),
      int_key("trigger.pulse_us", [](Config& c) -> int& { return c.trigger.pulse_us; }, {20, 100000}),
      int_key("trigger.frame_latency_us", [](Config& c) -> int& { return c.trigger.frame_latency_us; }, {0, 100000}),
      string_key("trigger.controller", [](Config& c) -> std::string& { return c.trigger.controller; }),

      enum_key<BackgroundMode>("silhouette.background", [](Config& c) -> BackgroundMode& { return c.silhouette.background; },
               {{"learn", BackgroundMode::Learn}, {"image", BackgroundMode::Image},
                {"threshold", BackgroundMode::Threshold}}),
      int_key("silhouette.learn_frames", [](Config& c) -> int& { return c.silhouette.learn_frames; }, {1, 1000}),
      int_key("silhouette.threshold", [](Config& c) -> int& { return c.silhouette.threshold; }, {1, 254}),
      int_key("silhouette.chroma_threshold", [](Config& c) -> int& { return c.silhouette.chroma_threshold; }, {0, 255}),
      double_key("silhouette.shadow_ratio", [](Config& c) -> double& { return c.silhouette.shadow_ratio; }, {0.0, 1.0}),
      int_key("silhouette.min_blob_px", [](Config& c) -> int& { return c.silhouette.min_blob_px; }, {1, 1000000}),
      string_key("silhouette.background_frontal", [](Config& c) -> std::string& { return c.silhouette.background_frontal; }),
      string_key("silhouette.background_lateral", [](Config& c) -> std::string& { return c.silhouette.background_lateral; }),
      double_key("silhouette.adapt_s", [](Config& c) -> double& { return c.silhouette.adapt_s; }, {0.0, 3600.0}),
      int_key("silhouette.adapt_margin_px", [](Config& c) -> int& { return c.silhouette.adapt_margin_px; }, {0, 64}),
      double_key("silhouette.relearn_empty_s", [](Config& c) -> double& { return c.silhouette.relearn_empty_s; }, {0.0, 86400.0}),
      bool_key("silhouette.bootstrap", [](Config& c) -> bool& { return c.silhouette.bootstrap; }),

      string_key("cvsm.model", [](Config& c) -> std::string& { return c.cvsm.model; }),
      int_key("cvsm.subject_frames", [](Config& c) -> int& { return c.cvsm.subject_frames; }, {0, 1000}),
      double_key("cvsm.lost_cost", [](Config& c) -> double& { return c.cvsm.lost_cost; }, {0.01, 2.0}),
      int_key("cvsm.refine_steps", [](Config& c) -> int& { return c.cvsm.refine_steps; }, {0, 4}),
      enum_key<LimbMode>("cvsm.limbs", [](Config& c) -> LimbMode& { return c.cvsm.limbs; },
               {{"fixed", LimbMode::Fixed}, {"articulated", LimbMode::Articulated}}),

      string_key("spine.model", [](Config& c) -> std::string& { return c.spine.model; }),
      double_key("spine.voxel_mm", [](Config& c) -> double& { return c.spine.voxel_mm; }, {0.25, 5.0}),
      int_key("spine.substeps", [](Config& c) -> int& { return c.spine.substeps; }, {1, 1000}),

      optional_double_key("subject.stature_mm", [](Config& c) -> double& { return c.subject.stature_mm; }, {1000.0, 2300.0}),
      optional_double_key("subject.mass_kg", [](Config& c) -> double& { return c.subject.mass_kg; }, {20.0, 250.0}),
      optional_double_key("subject.c7_height_mm", [](Config& c) -> double& { return c.subject.c7_height_mm; }, {800.0, 2000.0}),
      optional_double_key("subject.iliac_crest_height_mm", [](Config& c) -> double& { return c.subject.iliac_crest_height_mm; },
                          {500.0, 1400.0}),
      double_key("subject.height_mm", [](Config& c) -> double& { return c.subject.height_mm; }, {1000.0, 2300.0}),
      enum_key<SpinePlacementMode>("subject.spine_placement", [](Config& c) -> SpinePlacementMode& { return c.subject.spine_placement; },
               {{"measured", SpinePlacementMode::Measured}, {"generic", SpinePlacementMode::Generic}}),

      string_key("publish.listen", [](Config& c) -> std::string& { return c.publish.listen; }),
      bool_key("publish.allow_unauthenticated", [](Config& c) -> bool& { return c.publish.allow_unauthenticated; }),
      string_key("publish.unix_socket", [](Config& c) -> std::string& { return c.publish.unix_socket; }),
      string_key("publish.unix_socket_group", [](Config& c) -> std::string& { return c.publish.unix_socket_group; }),
      int_key("publish.client_queue", [](Config& c) -> int& { return c.publish.client_queue; }, {1, 100000}),
      int_key("publish.max_clients", [](Config& c) -> int& { return c.publish.max_clients; }, {1, 1024}),
      string_key("publish.tls_cert", [](Config& c) -> std::string& { return c.publish.tls_cert; }),
      string_key("publish.tls_key", [](Config& c) -> std::string& { return c.publish.tls_key; }),
      string_key("publish.tls_client_ca", [](Config& c) -> std::string& { return c.publish.tls_client_ca; }),
      string_key("publish.token_file", [](Config& c) -> std::string& { return c.publish.token_file; }),
      double_key("publish.auth_timeout_s", [](Config& c) -> double& { return c.publish.auth_timeout_s; }, {0.1, 300.0}),

      int_key("exposure.interval_s", [](Config& c) -> int& { return c.exposure.interval_s; }, {1, 86400}),

      bool_key("alerts.enabled", [](Config& c) -> bool& { return c.alerts.enabled; }),
      string_key("alerts.rules", [](Config& c) -> std::string& { return c.alerts.rules; }),
      bool_key("alerts.silent", [](Config& c) -> bool& { return c.alerts.silent; }),
      string_key("alerts.gpio_chip", [](Config& c) -> std::string& { return c.alerts.gpio_chip; }),
      int_key("alerts.gpio_line", [](Config& c) -> int& { return c.alerts.gpio_line; }, {0, 1023}),
      bool_key("alerts.gpio_active_low", [](Config& c) -> bool& { return c.alerts.gpio_active_low; }),
      string_key("alerts.gpio_mode", [](Config& c) -> std::string& { return c.alerts.gpio_mode; }, {"steady", "pulse"}),
      int_key("alerts.pulse_ms", [](Config& c) -> int& { return c.alerts.pulse_ms; }, {20, 60000}),

      string_key("storage.path", [](Config& c) -> std::string& { return c.storage.path; }),
      int_key("storage.posture_every", [](Config& c) -> int& { return c.storage.posture_every; }, {1, 1000000}),
      double_key("storage.retention_days", [](Config& c) -> double& { return c.storage.retention_days; }, {1e-5, 36500.0}),
      double_key("storage.max_size_mb", [](Config& c) -> double& { return c.storage.max_size_mb; }, {0.0, 1e7}),
      string_key("http.listen", [](Config& c) -> std::string& { return c.http.listen; }),
      bool_key("http.allow_unauthenticated", [](Config& c) -> bool& { return c.http.allow_unauthenticated; }),
      double_key("http.fps", [](Config& c) -> double& { return c.http.fps; }, {0.2, 30.0}),
      bool_key("http.camera_pixels", [](Config& c) -> bool& { return c.http.camera_pixels; }),
      int_key("http.max_connections", [](Config& c) -> int& { return c.http.max_connections; }, {1, 256}),
      double_key("http.timeout_s", [](Config& c) -> double& { return c.http.timeout_s; }, {0.5, 300.0}),
      string_key("http.tls_cert", [](Config& c) -> std::string& { return c.http.tls_cert; }),
      string_key("http.tls_key", [](Config& c) -> std::string& { return c.http.tls_key; }),
      string_key("http.tls_client_ca", [](Config& c) -> std::string& { return c.http.tls_client_ca; }),
      string_key("http.token_file", [](Config& c) -> std::string& { return c.http.token_file; }),

      string_key("log.level", [](Config& c) -> std::string& { return c.log.level; },
                 {"trace", "debug", "info", "warn", "error"}),
      int_key("log.status_interval_s", [](Config& c) -> int& { return c.log.status_interval_s; }, {1, 86400}),

      mqtt_url_key(),
      string_key("mqtt.ca_file", [](Config& c) -> std::string& { return c.mqtt.ca_file; }),
      string_key("mqtt.cert_file", [](Config& c) -> std::string& { return c.mqtt.cert_file; }),
      string_key("mqtt.key_file", [](Config& c) -> std::string& { return c.mqtt.key_file; }),
      string_key("mqtt.username", [](Config& c) -> std::string& { return c.mqtt.username; }),
      string_key("mqtt.password_file", [](Config& c) -> std::string& { return c.mqtt.password_file; }),
      double_key("mqtt.posture_rate_hz", [](Config& c) -> double& { return c.mqtt.posture_rate_hz; }, {0.0, 120.0}),
      int_key("mqtt.qos", [](Config& c) -> int& { return c.mqtt.qos; }, {0, 1}),
      string_key("mqtt.outbox_path", [](Config& c) -> std::string& { return c.mqtt.outbox_path; }),
      int_key("mqtt.outbox_max_messages", [](Config& c) -> int& { return c.mqtt.outbox_max_messages; }, {1, 10000000}),
      int_key("mqtt.keepalive_s", [](Config& c) -> int& { return c.mqtt.keepalive_s; }, {5, 3600}),
      double_key("mqtt.reconnect_min_s", [](Config& c) -> double& { return c.mqtt.reconnect_min_s; }, {0.1, 3600.0}),
      double_key("mqtt.reconnect_max_s", [](Config& c) -> double& { return c.mqtt.reconnect_max_s; }, {0.1, 86400.0}),
      bool_key("privacy.pseudonymise", [](Config& c) -> bool& { return c.privacy.pseudonymise; }),
      string_key("privacy.secret_file", [](Config& c) -> std::string& { return c.privacy.secret_file; }),
  };
  return table;
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

namespace {

const Key* find_key(const std::string& name) {
  for (const auto& k : keys())
    if (k.name == name) return &k;
  return nullptr;
}

bool known_section(std::string_view section) {
  for (const auto& k : keys())
    if (std::string_view(k.name).substr(0, k.name.find('.')) == section) return true;
  return false;
}

std::string at(std::string_view source, const toml::node& n) {
  return fmt::format("{}:{}", source, n.source().begin.line);
}

// The [mqtt] keys taken together: the key at fault and the problem.
std::optional<std::pair<std::string, std::string>> check_mqtt(const Config::Mqtt& m) {
  const bool tls = m.url.rfind("mqtts://", 0) == 0;
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
  for (const auto& k : keys()) names.push_back(k.name);
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
      const Key* k = find_key(name);
      if (!k) {
        // A key a release renamed: the message says what to write instead.
        for (const auto& [was, now] : kRenamedKeys)
          if (name == was) return Error{fmt::format("{}: {}: unknown key; it is now {}", at(source, value), name, now)};
        return Error{fmt::format("{}: {}: unknown key{}", at(source, value), name, did_you_mean(name, config_keys()))};
      }
      if (auto problem = k->set(config, value))
        return Error{fmt::format("{}: {}: {}", at(source, value), name, *problem)};
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

KnownWorker known_worker(const Config::Subject& s) {
  // 0 = not known, for every key of the worker.
  auto known = [](double v) { return v > 0 ? std::optional<double>(v) : std::nullopt; };
  return {known(s.stature_mm), known(s.mass_kg), known(s.c7_height_mm), known(s.iliac_crest_height_mm)};
}

Result<Config> load_config(const std::filesystem::path& path) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  return parse_config(*text, path.string());
}

}  // namespace spinewatch
