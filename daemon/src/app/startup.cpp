#include "app/startup.hpp"

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "access/network_access.hpp"
#include "net/unix_listener.hpp"
#include "spinewatch/capture/recording.hpp"
#include "spinewatch/sync/gpiod_trigger_line.hpp"
#include "support/station_dirs.hpp"

namespace spinewatch {

// The recording's own calibration describes the rig it was made with; then
// the station's; then the documented default rig.
Result<CameraRig> load_rig(const Config& config, const SourcePlan& plan, std::string& used) {
  std::vector<std::filesystem::path> candidates;
  if (plan.kind == SourcePlan::Kind::Recording) candidates.push_back(plan.recording / "calibration.yaml");
  candidates.emplace_back(config.cameras.calibration);
  for (const auto& path : candidates) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) continue;
    auto rig = load_calibration(path);
    if (!rig) return rig.error();
    // A calibration made at another resolution does not describe these frames.
    int width = config.cameras.width, height = config.cameras.height;
    if (plan.kind == SourcePlan::Kind::Recording)
      if (auto reader = RecordingReader::open(plan.recording)) {
        width = static_cast<int>(reader->info().format.width);
        height = static_cast<int>(reader->info().format.height);
      }
    if (auto s = check_image_size(*rig, width, height); !s) return Error{path.string() + ": " + s.error().message};
    spdlog::info("calibration: {}", path.string());
    used = path.string();
    return rig;
  }
  spdlog::warn("calibration: {} not found; using the default rig ({}; docs/calibration.md, \"The default rig\"); set "
               "cameras.calibration to the station's calibration.yaml (spinewatch calibrate)",
               config.cameras.calibration.empty() ? "none given" : config.cameras.calibration,
               CameraRig::kDefaultRigSummary);
  used.clear();
  return CameraRig::default_rig();
}

// The empty scene (docs/tuning.md, "Background"): a replayed recording's
// own background_*.png describe its scene; then the station's stored
// images (silhouette.background_frontal/_lateral); else none, and the
// estimator learns or bootstraps one (background = "learn") — or, with
// background = "image", the daemon refuses to start.
Result<std::optional<BackgroundImages>> load_background(const Config& config, const SourcePlan& plan) {
  const Config::Silhouette& s = config.silhouette;
  if (s.background == BackgroundMode::Threshold) return std::optional<BackgroundImages>{};
  int width = config.cameras.width, height = config.cameras.height;
  if (plan.kind == SourcePlan::Kind::Recording) {
    auto reader = RecordingReader::open(plan.recording);
    if (!reader) return reader.error();
    width = static_cast<int>(reader->info().format.width);
    height = static_cast<int>(reader->info().format.height);
    if (has_background_images(plan.recording)) {
      auto images = load_background_images(plan.recording, width, height);
      if (!images) return images.error();
      spdlog::info("background: the recording's {} and {}", kBackgroundFiles[0], kBackgroundFiles[1]);
      return std::optional<BackgroundImages>(std::move(images).value());
    }
  }
  if (!s.background_frontal.empty() || !s.background_lateral.empty()) {
    if (s.background_frontal.empty() || s.background_lateral.empty())
      return Error{fmt::format("silhouette.background_{}: empty, while the other view's is set; give both",
                               s.background_frontal.empty() ? "frontal" : "lateral")};
    auto images = load_background_images(s.background_frontal, s.background_lateral, width, height);
    if (!images) return Error{"silhouette.background_frontal/_lateral: " + images.error().message};
    spdlog::info("background: {} and {}", s.background_frontal, s.background_lateral);
    return std::optional<BackgroundImages>(std::move(images).value());
  }
  if (s.background == BackgroundMode::Image)
    return Error{"silhouette.background = \"image\" needs silhouette.background_frontal and background_lateral "
                 "(capture them with `spinewatch background --out DIR`)"};
  spdlog::info("background: none stored; learnt from the first frames of an empty scene, or bootstrapped when "
               "someone is in view (silhouette.bootstrap)");
  return std::optional<BackgroundImages>{};
}

Result<PublisherOptions> publisher_options(const Config& config, const DaemonOverrides& overrides) {
  PublisherOptions o;
  const std::string listen = overrides.listen.value_or(config.publish.listen);
  if (listen != "none") {
    const std::string where = overrides.listen ? "--listen " : "publish.listen: ";
    auto endpoint = parse_listen_address(listen);
    if (!endpoint) return Error{where + endpoint.error().message};
    const Config::Publish& c = config.publish;
    auto access = load_access({c.tls_cert, c.tls_key, c.tls_client_ca, c.token_file}, "publish");
    if (!access) return access.error();
    // Safe by default (docs/security.md): the stream is health data about
    // identifiable workers; a network bind needs TLS and an authentication,
    // or the site's explicit acceptance.
    if (exposed_unprotected(*endpoint, *access) && !c.allow_unauthenticated)
      return Error{fmt::format(
          "{}{}: not a loopback address, and the posture stream is not protected ({}): anyone who can reach the "
          "port would read the workers' postures. Set [publish] tls_cert and tls_key with token_file or "
          "tls_client_ca, or listen on 127.0.0.1 (and reach it through an SSH tunnel), or set [publish] "
          "allow_unauthenticated = true to accept that (docs/security.md)",
          where, listen, access->describe())};
    o.access = std::move(access).value();
    o.auth_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(c.auth_timeout_s * 1000));
    o.tcp = *endpoint;
  }
  const std::string unix_path = overrides.unix_socket.value_or(config.publish.unix_socket);
  if (unix_path == "") {
    auto path = default_unix_socket_path();
    if (!path) return path.error();
    o.unix_socket = std::move(path).value();
  } else if (unix_path != "none") {
    o.unix_socket = std::filesystem::path(unix_path);
  }
  if (o.unix_socket && !config.publish.unix_socket_group.empty()) {
    auto gid = group_id(config.publish.unix_socket_group, "publish.unix_socket_group");
    if (!gid) return gid.error();
    o.unix_socket_gid = *gid;
  }
  if (!o.tcp && !o.unix_socket) return Error{"publishing is off on both TCP and the Unix socket: nothing would be served"};
  o.client_queue = static_cast<std::size_t>(config.publish.client_queue);
  o.max_clients = static_cast<std::size_t>(config.publish.max_clients);
  return o;
}

// The live view (http.listen, --http), off when "" or "none"; loopback
// unless allowed, exactly as the posture stream's TCP listener.
Result<std::optional<HttpOptions>> http_options(const Config& config, const DaemonOverrides& overrides) {
  const std::string listen = overrides.http.value_or(config.http.listen);
  if (listen.empty() || listen == "none") return std::optional<HttpOptions>{};
  const std::string where = overrides.http ? "--http " : "http.listen: ";
  auto endpoint = parse_listen_address(listen);
  if (!endpoint) return Error{where + endpoint.error().message};
  const Config::Http& c = config.http;
  auto access = load_access({c.tls_cert, c.tls_key, c.tls_client_ca, c.token_file}, "http");
  if (!access) return access.error();
  if (exposed_unprotected(*endpoint, *access) && !c.allow_unauthenticated)
    return Error{fmt::format(
        "{}{}: not a loopback address, and the live view is not protected ({}): anyone who can reach the port "
        "would see the station's views and the workers' postures. Set [http] tls_cert and tls_key with token_file "
        "or tls_client_ca, or listen on 127.0.0.1 (and reach it through an SSH tunnel: docs/daemon.md), or set "
        "[http] allow_unauthenticated = true to accept that (docs/security.md)",
        where, listen, access->describe())};
  HttpOptions o;
  o.endpoint = *endpoint;
  o.access = std::move(access).value();
  o.max_connections = static_cast<std::size_t>(config.http.max_connections);
  o.timeout = std::chrono::milliseconds(static_cast<std::int64_t>(config.http.timeout_s * 1000));
  return std::optional<HttpOptions>(o);
}

// [alerts] gpio_chip: the buzzer's or lamp's line. A line that cannot be
// opened is an error value here; the caller logs it once and runs on.
Result<std::unique_ptr<AlertOutput>> open_alert_output(const Config::Alerts& a) {
  auto line = sync::open_gpiod_output(a.gpio_chip, static_cast<unsigned>(a.gpio_line), "spinewatch-alert",
                                      a.gpio_active_low);
  if (!line) return line.error();
  return std::make_unique<AlertOutput>(
      std::move(line).value(),
      AlertOutputOptions{.mode = a.gpio_mode, .pulse = std::chrono::milliseconds(a.pulse_ms), .silent = a.silent},
      fmt::format("GPIO {} line {}", a.gpio_chip, a.gpio_line));
}

}  // namespace spinewatch
