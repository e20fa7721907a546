#pragma once
// The station's TOML configuration (docs/interfaces.md §6): the aggregate of
// its components' sections. Each section is a struct whose members hold the
// values and their defaults, with its key table beside it (name, type,
// range, reload; frames/option_table.hpp): the estimator's in
// estimator/estimator_config.hpp, the daemon's below (tables in
// config_keys.cpp). config/spinewatch.toml documents every key at its
// default, and a test checks it against the tables (docs/configuration.md).
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/daemon/logging.hpp"
#include "spinewatch/estimator/estimator_config.hpp"
#include "spinewatch/frames/option_table.hpp"
#include "spinewatch/frames/pixel_format.hpp"
#include "spinewatch/frames/result.hpp"
#include "spinewatch/sync/trigger_source.hpp"

namespace spinewatch {

// The modes of the configuration, parsed once when it is read (the loader's
// table holds each mode's names); code switches on these, never on text.
enum class CameraSource : std::uint8_t {
  Auto,       // cameras when both nodes are there, else the embedded recording
  V4l2,       // the two V4L2 nodes, or an error
  Libcamera,  // two libcamera cameras by id, or an error
  Recording,  // cameras.recording (or the embedded default)
};
enum class ReplayPace : std::uint8_t {
  Paced,  // a recording at its own rate, like cameras
  Fast,   // as fast as the estimator takes pairs
};
// [alerts] gpio_mode: how an output line signals a raised alert.
enum class AlertSignalMode : std::uint8_t {
  Steady,  // active while any alert is raised
  Pulse,   // on pulse, off pulse, … while any alert is raised
};
std::string_view to_string(CameraSource source);
std::string_view to_string(ReplayPace pace);
std::string_view to_string(AlertSignalMode mode);

struct Config {
  struct Station {
    std::string name = "spinewatch";
    bool operator==(const Station&) const = default;
    static const OptionTable<Station>& keys();
  } station;

  struct Cameras {
    CameraSource source = CameraSource::Auto;
    std::string frontal = "/dev/video0";  // V4L2 node, or a libcamera id when source = "libcamera"
    std::string lateral = "/dev/video2";
    PixelFormat pixel_format = PixelFormat::YUYV;
    int width = 320;
    int height = 240;
    double fps = 30.0;
    int exposure_us = 8000;  // 0: leave exposure to the driver
    int gain = -1;           // -1: leave gain to the driver
    int buffers = 4;
    std::string calibration = "/etc/spinewatch/calibration.yaml";
    std::string recording = "";  // "" with source=auto/recording: the embedded phantom default
    ReplayPace replay = ReplayPace::Paced;  // how spinewatchd replays a recording
    double watchdog_s = 2.0;
    bool operator==(const Cameras&) const = default;
    static const OptionTable<Cameras>& keys();
  } cameras;

  struct Trigger {
    sync::TriggerMode mode = sync::TriggerMode::FreeRun;
    std::string chip = "gpiochip0";
    int line = 17;
    int pulse_us = 1000;
    int frame_latency_us = 0;  // trigger edge → frame timestamp, both cameras
    std::string controller = "";  // serial device of the trigger controller, "" for none
    bool operator==(const Trigger&) const = default;
    static const OptionTable<Trigger>& keys();
  } trigger;

  using Silhouette = SilhouetteConfig;  // the estimator's (estimator_config.hpp)
  Silhouette silhouette;

  using Cvsm = CvsmConfig;  // the estimator's (estimator_config.hpp)
  Cvsm cvsm;

  using Spine = SpineConfig;  // the estimator's (estimator_config.hpp)
  Spine spine;

  using Subject = SubjectConfig;  // the estimator's (estimator_config.hpp)
  Subject subject;

  struct Publish {
    std::string listen = "127.0.0.1:7117";  // HOST:PORT or "none"
    std::string unix_socket = "";           // "" = $RUNTIME_DIRECTORY/posture.sock, "none" = off
    std::string unix_socket_group = "";     // the socket's group (mode 0660); "" = the daemon's
    int client_queue = 256;                 // lines buffered per client before it is dropped
    int max_clients = 32;
    // The stream has no authentication yet (docs/security.md): a TCP address
    // that is not loopback is refused at start unless this says the site
    // accepts that anyone who can reach the port reads the postures.
    bool allow_unauthenticated = false;
    // TLS and authentication on the TCP port (docs/security.md); "" = off.
    std::string tls_cert = "", tls_key = "", tls_client_ca = "", token_file = "";
    double auth_timeout_s = 10.0;  // the TLS handshake and the auth line must be done within this
    bool operator==(const Publish&) const = default;
    static const OptionTable<Publish>& keys();
  } publish;

  struct Exposure {
    int interval_s = 60;  // length of each exposure summary (docs/exposure.md)
    bool operator==(const Exposure&) const = default;
    static const OptionTable<Exposure>& keys();
  } exposure;

  struct Alerts {
    bool enabled = true;    // alert rules run and their lines are published (docs/exposure.md, "Alerts")
    std::string rules = "";  // rules file ([[rule]] tables); "" = the built-in config/alerts.toml
    bool silent = false;     // record alerts (lines, database), never signal them (no GPIO)
    std::string gpio_chip = "";  // the buzzer's or lamp's GPIO chip; "" = no output line
    int gpio_line = 0;           // its line offset on the chip
    bool gpio_active_low = false;  // active = the pin driven low
    AlertSignalMode gpio_mode = AlertSignalMode::Steady;
    int pulse_ms = 500;                // pulse: on this long, off this long
    bool operator==(const Alerts&) const = default;
    static const OptionTable<Alerts>& keys();
  } alerts;

  struct Storage {
    std::string path = "";          // the SQLite database; "" = nothing stored (docs/storage.md)
    int posture_every = 30;         // store every Nth posture (30: once a second at 30 fps)
    double retention_days = 90;     // rows older than this are deleted
    double max_size_mb = 0;         // the database's size limit; 0 = the disk's
    bool operator==(const Storage&) const = default;
    static const OptionTable<Storage>& keys();
  } storage;
  struct Http {
    // The live view and /metrics (docs/interfaces.md §5): HOST:PORT, or "" / "none" = off.
    std::string listen = "";
    // Like publish.allow_unauthenticated, for the HTTP server: a non-loopback
    // address is refused at start unless this is true.
    bool allow_unauthenticated = false;
    double fps = 5.0;            // live view pictures a second at most, drawn only while someone watches
    bool camera_pixels = false;  // the views over the cameras' pixels; false: a plain background (privacy)
    int max_connections = 16;
    double timeout_s = 10.0;     // a request must arrive, and each response or stream frame be taken, within this
    // As [publish]'s: TLS, client certificates, bearer tokens; "" = off.
    std::string tls_cert = "", tls_key = "", tls_client_ca = "", token_file = "";
    bool operator==(const Http&) const = default;
    static const OptionTable<Http>& keys();
  } http;

  struct Log {
    LogLevel level = LogLevel::Info;
    int status_interval_s = 60;
    bool operator==(const Log&) const = default;
    static const OptionTable<Log>& keys();
  } log;

  struct Mqtt {
    // The site's MQTT broker (docs/interfaces.md §7, docs/fleet.md):
    // "mqtt://HOST:PORT" or "mqtts://HOST:PORT"; "" = off.
    std::string url = "";
    std::string ca_file = "";    // mqtts: the CA that signed the broker's certificate; "" = the system's CAs
    std::string cert_file = "";  // mqtts: this station's client certificate and key, both or neither
    std::string key_file = "";
    std::string username = "";
    std::string password_file = "";  // read at start; must not be readable by group or others
    double posture_rate_hz = 1.0;    // posture messages a second at most; 0 = none
    int qos = 0;                     // of the posture messages (summaries and alerts are always QoS 1)
    std::string outbox_path = "";    // summaries and alerts until the broker has them; "" = the state directory's
    int outbox_max_messages = 100000;  // beyond it the oldest is dropped (counted)
    int keepalive_s = 30;
    double reconnect_min_s = 1.0;    // back-off after a failed attempt, doubled up to reconnect_max_s
    double reconnect_max_s = 60.0;
    bool operator==(const Mqtt&) const = default;
    static const OptionTable<Mqtt>& keys();
  } mqtt;
  struct Privacy {
    // Worker ids (set_worker's "id") stored, published and logged as
    // pseudonyms, "w-" + 12 hex of HMAC-SHA256(secret, id) (docs/security.md).
    bool pseudonymise = true;
    // The station's secret; "" = $STATE_DIRECTORY/pseudonym.key (else
    // /var/lib/spinewatch/pseudonym.key), created 0600 when absent.
    std::string secret_file = "";
    bool operator==(const Privacy&) const = default;
    static const OptionTable<Privacy>& keys();
  } privacy;

  bool operator==(const Config&) const = default;
};

// Parses TOML text; `source` names it in error messages ("FILE:LINE: key: problem").
Result<Config> parse_config(std::string_view toml_text, std::string_view source);
Result<Config> load_config(const std::filesystem::path& path);
// Every key of the configuration, "section.key", section by section in the
// order of Config's members: the loader, the reload and the check of the
// annotated file all walk this one table.
const OptionTable<Config>& config_table();
// Every key the loader knows, "section.key", in declaration order.
std::vector<std::string> config_keys();
// A key's value as TOML writes it ("28", "0.5", "true", "\"learn\"").
std::string toml_text(const OptionValue& value);

// What is wrong with an annotated configuration (config/spinewatch.toml,
// `spinewatchd --print-config`): it must parse, list every key of
// config_table() and nothing else, each at the table's default. One
// message per problem ("FILE:LINE: key: problem"); none when it is right.
std::vector<std::string> annotated_config_problems(std::string_view toml_text, std::string_view source);

}  // namespace spinewatch
