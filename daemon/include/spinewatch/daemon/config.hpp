#pragma once
// The station's TOML configuration (docs/interfaces.md §6). Every key, its type,
// default and range is declared once in config_keys.cpp; config/spinewatch.toml
// is the annotated copy, and a test keeps the two in step.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/estimator/anatomy/spine_placement.hpp"
#include "spinewatch/estimator/anatomy/worker.hpp"
#include "spinewatch/estimator/cvsm/limb_mode.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
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
std::string_view to_string(CameraSource source);
std::string_view to_string(ReplayPace pace);

struct Config {
  struct Station {
    std::string name = "spinewatch";
    bool operator==(const Station&) const = default;
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
  } cameras;

  struct Trigger {
    sync::TriggerMode mode = sync::TriggerMode::FreeRun;
    std::string chip = "gpiochip0";
    int line = 17;
    int pulse_us = 1000;
    int frame_latency_us = 0;  // trigger edge → frame timestamp, both cameras
    std::string controller = "";  // serial device of the trigger controller, "" for none
    bool operator==(const Trigger&) const = default;
  } trigger;

  struct Silhouette {
    BackgroundMode background = BackgroundMode::Learn;
    int learn_frames = 10;
    int threshold = 28;        // grey levels above the background difference
    int chroma_threshold = 12; // chroma levels that make a pixel person whatever its luma (YUYV); 0 = luma only
    double shadow_ratio = 0.5; // darker down to this fraction, same colour: shadow, not person; 1 = keep shadows
    int min_blob_px = 600;
    std::string background_frontal = "";  // the station's empty scene (spinewatch background); "" = none
    std::string background_lateral = "";
    double adapt_s = 2.0;          // time constant of the background's adaptation outside the person; 0 = off
    int adapt_margin_px = 8;       // pixels around the person the adaptation leaves alone
    double relearn_empty_s = 10;   // an empty scene this long re-learns the whole background; 0 = never
    bool bootstrap = true;         // no background and someone in view: bootstrap one from their movement
    bool operator==(const Silhouette&) const = default;
  } silhouette;

  struct Cvsm {
    std::string model = "";  // "" = the generic model built in (config/cvsm-generic.toml)
    int subject_frames = 10;   // upright frames used to build the subject's model
    double lost_cost = 0.35;   // cost above which tracking is lost
    int refine_steps = 0;     // outline refinement of each fit: Gauss–Newton steps, 0 = off
    LimbMode limbs = LimbMode::Fixed;  // "fixed" or "articulated" (docs/cvsm.md, "Articulated limbs")
    bool operator==(const Cvsm&) const = default;
  } cvsm;

  struct Spine {
    std::string model = "";  // "" = the generic model built in
    double voxel_mm = 1.0;
    int substeps = 16;
    bool operator==(const Spine&) const = default;
  } spine;

  struct Subject {
    // The worker's, when known (0 = not known: the stature measured or
    // estimated from the silhouettes, the mass estimated from the stature).
    double stature_mm = 0;
    double mass_kg = 0;
    // Skin landmarks measured on the worker at set-up (0 = not known): they
    // place T1 and L5 (docs/anthropometry.md, "A known worker").
    double c7_height_mm = 0;
    double iliac_crest_height_mm = 0;
    double height_mm = 1750.0;  // the starting guess where the stature is not seen
    // Where the spine sits in the measured body: "measured" (regressions on
    // ANSUR II, docs/anthropometry.md) or "generic" (fixed fractions of height).
    SpinePlacementMode spine_placement = SpinePlacementMode::Measured;
    bool operator==(const Subject&) const = default;
  } subject;

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
  } publish;

  struct Exposure {
    int interval_s = 60;  // length of each exposure summary (docs/exposure.md)
    bool operator==(const Exposure&) const = default;
  } exposure;

  struct Alerts {
    bool enabled = true;    // alert rules run and their lines are published (docs/exposure.md, "Alerts")
    std::string rules = "";  // rules file ([[rule]] tables); "" = the built-in config/alerts.toml
    bool silent = false;     // record alerts (lines, database), never signal them (no GPIO)
    std::string gpio_chip = "";  // the buzzer's or lamp's GPIO chip; "" = no output line
    int gpio_line = 0;           // its line offset on the chip
    bool gpio_active_low = false;  // active = the pin driven low
    std::string gpio_mode = "steady";  // "steady" | "pulse" (AlertSignalMode)
    int pulse_ms = 500;                // pulse: on this long, off this long
    bool operator==(const Alerts&) const = default;
  } alerts;

  struct Storage {
    std::string path = "";          // the SQLite database; "" = nothing stored (docs/storage.md)
    int posture_every = 30;         // store every Nth posture (30: once a second at 30 fps)
    double retention_days = 90;     // rows older than this are deleted
    double max_size_mb = 0;         // the database's size limit; 0 = the disk's
    bool operator==(const Storage&) const = default;
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
  } http;

  struct Log {
    std::string level = "info";  // trace | debug | info | warn | error
    int status_interval_s = 60;
    bool operator==(const Log&) const = default;
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
  } mqtt;
  struct Privacy {
    // Worker ids (set_worker's "id") stored, published and logged as
    // pseudonyms, "w-" + 12 hex of HMAC-SHA256(secret, id) (docs/security.md).
    bool pseudonymise = true;
    // The station's secret; "" = $STATE_DIRECTORY/pseudonym.key (else
    // /var/lib/spinewatch/pseudonym.key), created 0600 when absent.
    std::string secret_file = "";
    bool operator==(const Privacy&) const = default;
  } privacy;

  bool operator==(const Config&) const = default;
};

// Parses TOML text; `source` names it in error messages ("FILE:LINE: key: problem").
Result<Config> parse_config(std::string_view toml_text, std::string_view source);
Result<Config> load_config(const std::filesystem::path& path);
// The [subject] keys of the worker (0 = not known).
KnownWorker known_worker(const Config::Subject& subject);

// Every key the loader knows, "section.key", in declaration order.
std::vector<std::string> config_keys();

}  // namespace spinewatch
