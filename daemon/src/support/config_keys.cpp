// The daemon's configuration keys, one entry per key, section by section;
// the estimator's sections are in estimator/src/pipeline/estimator_config.cpp.
// A new key: its member (with its default) in config.hpp, its entry here,
// its line in config/spinewatch.toml (docs/configuration.md, "Adding a key").
// A key applied by a reload without a restart says .live() and is applied
// in the daemon's reload.
#include "spinewatch/daemon/config.hpp"
#include "support/mqtt_url.hpp"

namespace spinewatch {

const OptionTable<Config::Station>& Config::Station::keys() {
  using S = Config::Station;
  static const OptionTable<S> table = {
      text_key("name", &S::name).live(),
  };
  return table;
}

const OptionTable<Config::Cameras>& Config::Cameras::keys() {
  using S = Config::Cameras;
  static const OptionTable<S> table = {
      mode_key("source", &S::source,
               {{"auto", CameraSource::Auto}, {"v4l2", CameraSource::V4l2}, {"libcamera", CameraSource::Libcamera},
                {"recording", CameraSource::Recording}}),
      // V4L2 device nodes, or libcamera camera ids when cameras.source = "libcamera".
      text_key("frontal", &S::frontal),
      text_key("lateral", &S::lateral),
      mode_key("pixel_format", &S::pixel_format, {{"YUYV", PixelFormat::YUYV}, {"GREY", PixelFormat::GREY}}),
      integer_key("width", &S::width, 16, 4096),
      integer_key("height", &S::height, 16, 4096),
      number_key("fps", &S::fps, 1.0, 120.0),
      integer_key("exposure_us", &S::exposure_us, 0, 1000000),
      integer_key("gain", &S::gain, -1, 100000),
      integer_key("buffers", &S::buffers, 4, 32),
      text_key("calibration", &S::calibration),
      text_key("recording", &S::recording),
      mode_key("replay", &S::replay, {{"paced", ReplayPace::Paced}, {"fast", ReplayPace::Fast}}),
      number_key("watchdog_s", &S::watchdog_s, 0.1, 60.0),
  };
  return table;
}

const OptionTable<Config::Trigger>& Config::Trigger::keys() {
  using S = Config::Trigger;
  static const OptionTable<S> table = {
      mode_key("mode", &S::mode,
               {{"free-run", sync::TriggerMode::FreeRun}, {"master", sync::TriggerMode::Master},
                {"slave", sync::TriggerMode::Slave}}),
      text_key("chip", &S::chip),
      integer_key("line", &S::line, 0, 1023),
      integer_key("pulse_us", &S::pulse_us, 20, 100000),
      integer_key("frame_latency_us", &S::frame_latency_us, 0, 100000),
      text_key("controller", &S::controller),
  };
  return table;
}

const OptionTable<Config::Publish>& Config::Publish::keys() {
  using S = Config::Publish;
  static const OptionTable<S> table = {
      text_key("listen", &S::listen),
      flag_key("allow_unauthenticated", &S::allow_unauthenticated),
      text_key("unix_socket", &S::unix_socket),
      text_key("unix_socket_group", &S::unix_socket_group),
      integer_key("client_queue", &S::client_queue, 1, 100000),
      integer_key("max_clients", &S::max_clients, 1, 1024),
      text_key("tls_cert", &S::tls_cert),
      text_key("tls_key", &S::tls_key),
      text_key("tls_client_ca", &S::tls_client_ca),
      text_key("token_file", &S::token_file),
      number_key("auth_timeout_s", &S::auth_timeout_s, 0.1, 300.0),
  };
  return table;
}

const OptionTable<Config::Exposure>& Config::Exposure::keys() {
  using S = Config::Exposure;
  static const OptionTable<S> table = {
      integer_key("interval_s", &S::interval_s, 1, 86400),
  };
  return table;
}

const OptionTable<Config::Alerts>& Config::Alerts::keys() {
  using S = Config::Alerts;
  static const OptionTable<S> table = {
      flag_key("enabled", &S::enabled),
      text_key("rules", &S::rules),
      flag_key("silent", &S::silent).live(),
      text_key("gpio_chip", &S::gpio_chip),
      integer_key("gpio_line", &S::gpio_line, 0, 1023),
      flag_key("gpio_active_low", &S::gpio_active_low),
      mode_key("gpio_mode", &S::gpio_mode, {{"steady", AlertSignalMode::Steady}, {"pulse", AlertSignalMode::Pulse}}),
      integer_key("pulse_ms", &S::pulse_ms, 20, 60000),
  };
  return table;
}

const OptionTable<Config::Storage>& Config::Storage::keys() {
  using S = Config::Storage;
  static const OptionTable<S> table = {
      text_key("path", &S::path),
      integer_key("posture_every", &S::posture_every, 1, 1000000),
      number_key("retention_days", &S::retention_days, 1e-5, 36500.0),
      number_key("max_size_mb", &S::max_size_mb, 0.0, 1e7),
  };
  return table;
}

const OptionTable<Config::Http>& Config::Http::keys() {
  using S = Config::Http;
  static const OptionTable<S> table = {
      text_key("listen", &S::listen),
      flag_key("allow_unauthenticated", &S::allow_unauthenticated),
      number_key("fps", &S::fps, 0.2, 30.0),
      flag_key("camera_pixels", &S::camera_pixels),
      integer_key("max_connections", &S::max_connections, 1, 256),
      number_key("timeout_s", &S::timeout_s, 0.5, 300.0),
      text_key("tls_cert", &S::tls_cert),
      text_key("tls_key", &S::tls_key),
      text_key("tls_client_ca", &S::tls_client_ca),
      text_key("token_file", &S::token_file),
  };
  return table;
}

const OptionTable<Config::Log>& Config::Log::keys() {
  using S = Config::Log;
  static const OptionTable<S> table = {
      mode_key("level", &S::level, log_level_names()).live(),
      integer_key("status_interval_s", &S::status_interval_s, 1, 86400).live(),
  };
  return table;
}

const OptionTable<Config::Mqtt>& Config::Mqtt::keys() {
  using S = Config::Mqtt;
  // mqtt.url: "" (off) or a URL parse_mqtt_url takes.
  auto mqtt_url = [](const std::string& url) -> std::optional<std::string> {
    if (url.empty()) return std::nullopt;
    if (auto parsed = parse_mqtt_url(url); !parsed) return parsed.error().message;
    return std::nullopt;
  };
  static const OptionTable<S> table = {
      text_key("url", &S::url).checked_by(mqtt_url),
      text_key("ca_file", &S::ca_file),
      text_key("cert_file", &S::cert_file),
      text_key("key_file", &S::key_file),
      text_key("username", &S::username),
      text_key("password_file", &S::password_file),
      number_key("posture_rate_hz", &S::posture_rate_hz, 0.0, 120.0),
      integer_key("qos", &S::qos, 0, 1),
      text_key("outbox_path", &S::outbox_path),
      integer_key("outbox_max_messages", &S::outbox_max_messages, 1, 10000000),
      integer_key("keepalive_s", &S::keepalive_s, 5, 3600),
      number_key("reconnect_min_s", &S::reconnect_min_s, 0.1, 3600.0),
      number_key("reconnect_max_s", &S::reconnect_max_s, 0.1, 86400.0),
  };
  return table;
}

const OptionTable<Config::Privacy>& Config::Privacy::keys() {
  using S = Config::Privacy;
  static const OptionTable<S> table = {
      flag_key("pseudonymise", &S::pseudonymise),
      text_key("secret_file", &S::secret_file),
  };
  return table;
}

// The aggregate: every section in the order of Config's members.
const OptionTable<Config>& config_table() {
  static const OptionTable<Config> table = [] {
    OptionTable<Config> t;
    add_section(t, "station", &Config::station, Config::Station::keys());
    add_section(t, "cameras", &Config::cameras, Config::Cameras::keys());
    add_section(t, "trigger", &Config::trigger, Config::Trigger::keys());
    add_section(t, "silhouette", &Config::silhouette, SilhouetteConfig::keys());
    add_section(t, "cvsm", &Config::cvsm, CvsmConfig::keys());
    add_section(t, "spine", &Config::spine, SpineConfig::keys());
    add_section(t, "subject", &Config::subject, SubjectConfig::keys());
    add_section(t, "publish", &Config::publish, Config::Publish::keys());
    add_section(t, "exposure", &Config::exposure, Config::Exposure::keys());
    add_section(t, "alerts", &Config::alerts, Config::Alerts::keys());
    add_section(t, "storage", &Config::storage, Config::Storage::keys());
    add_section(t, "http", &Config::http, Config::Http::keys());
    add_section(t, "log", &Config::log, Config::Log::keys());
    add_section(t, "mqtt", &Config::mqtt, Config::Mqtt::keys());
    add_section(t, "privacy", &Config::privacy, Config::Privacy::keys());
    return t;
  }();
  return table;
}

}  // namespace spinewatch
