// Where the station's outputs are opened and listed. A new output is a
// PostureSink (posture_sink.hpp) in daemon/src/outputs/, opened here and
// added to the list in open_outputs() at its place in the stop order.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "access/network_access.hpp"
#include "app/daemon_impl.hpp"
#include "app/startup.hpp"
#include "publish/stream_lines.hpp"
#include "spinewatch/daemon/exposure_options.hpp"

namespace spinewatch {

namespace {

// An unauthenticated network listener: said to every client and logged.
void warn_unprotected(std::vector<std::string>& warnings, std::string_view scheme, const TcpEndpoint& endpoint,
                      const Access& access, std::string_view what, std::string_view key) {
  auto warning = unprotected_warning(scheme, endpoint, access, what, key);
  if (!warning) return;
  warnings.push_back(std::move(*warning));
  spdlog::warn("{}", warnings.back());
}

// [alerts] gpio_chip: the buzzer's or lamp's line. One that cannot be
// opened is logged once and said to every client; the station runs on and
// records alerts.
std::unique_ptr<AlertLineSink> open_alert_line(const Config::Alerts& a, std::vector<std::string>& warnings) {
  if (a.gpio_chip.empty()) return nullptr;
  if (!a.enabled) {
    spdlog::info("alerts.enabled = false: the alert line {} line {} is not used", a.gpio_chip, a.gpio_line);
    return nullptr;
  }
  auto output = open_alert_output(a);
  if (!output) {
    warnings.push_back(fmt::format("alerts not signalled: {} (alerts.gpio_chip)", output.error().message));
    spdlog::error("{}", warnings.back());
    return std::make_unique<AlertLineSink>();
  }
  spdlog::info("alerts: signalled on {} ({}, {}{})", (*output)->name(), to_string(a.gpio_mode),
               a.gpio_active_low ? "active low" : "active high", a.silent ? "; silent for now" : "");
  return std::make_unique<AlertLineSink>(std::move(output).value());
}

Result<std::unique_ptr<MqttSink>> open_mqtt(const Config& config) {
  auto options = mqtt_options(config);
  if (!options) return options.error();
  if (!*options) return std::unique_ptr<MqttSink>();
  auto mqtt = MqttPublisher::start(std::move(**options));
  if (!mqtt) return mqtt.error();
  const Config::Mqtt& c = config.mqtt;
  spdlog::info("mqtt: publishing to {} under {}* (postures at {} Hz at most, QoS {}; outbox {})", c.url,
               (*mqtt)->prefix(), c.posture_rate_hz, c.qos,
               c.outbox_path.empty() ? "in the state directory" : c.outbox_path);
  return std::make_unique<MqttSink>(std::move(mqtt).value());
}

}  // namespace

Status Daemon::Impl::open_outputs(std::vector<std::unique_ptr<PostureSink>> extra) {
  auto options = publisher_options(config, overrides);
  if (!options) return options.error();
  options->on_input = [this](std::string_view line, const std::string& client) {
    return workers.on_client_line(line, client);
  };
  if (options->tcp) warn_unprotected(hello_warnings, "tcp", *options->tcp, options->access, "posture stream", "publish.allow_unauthenticated");
  auto http = http_options(config, overrides);
  if (!http) return http.error();
  if (*http) warn_unprotected(hello_warnings, "http", (*http)->endpoint, (*http)->access, "live view", "http.allow_unauthenticated");
  alerts_silent = config.alerts.silent;
  auto alert = open_alert_line(config.alerts, hello_warnings);
  const bool alert_line_failed = alert && !alert->is_open();  // its warning is the last one

  // Both servers' I/O thread: the publisher's clients and, with --http, the live view's.
  network = std::make_unique<net::NetworkLoop>("network");
  auto started = Publisher::start(network->io(), *options,
                                  make_hello_line(config.station.name, rig, source_name, hello_warnings));
  if (!started) return started.error();
  auto publisher_sink = std::make_unique<PublisherSink>(std::move(started).value());
  publisher = &publisher_sink->publisher();
  if (options->tcp)
    spdlog::info("publishing on tcp {}:{} ({})", options->tcp->host, publisher->tcp_port(), options->access.describe());
  if (options->unix_socket) spdlog::info("publishing on unix socket {}", options->unix_socket->string());

  std::unique_ptr<StoreSink> store;
  if (!config.storage.path.empty()) {
    store = std::make_unique<StoreSink>(std::make_unique<Store>(store_options(config)),
                                        static_cast<std::uint64_t>(config.storage.posture_every));
    store->on_note(NoteLevel::Info, fmt::format("started: source {}", source_name));
    if (alert_line_failed) store->on_note(NoteLevel::Error, hello_warnings.back());
  }
  auto mqtt = open_mqtt(config);
  if (!mqtt) return mqtt.error();
  std::unique_ptr<LiveViewSink> live;
  if (*http) {
    const Config::Http& h = config.http;
    live = std::make_unique<LiveViewSink>(
        rig, LiveViewOptions{.fps = h.fps, .camera_pixels = h.camera_pixels, .note = config.station.name});
  }

  // The list, in the order the outputs stop: the alert line first (the
  // buzzer or lamp off before anything else), MQTT (sends what it can,
  // says "offline"), the live view and its server, the publisher (both
  // close their clients on the network loop, which stops after the
  // outputs), the store (it records the stop), then the caller's.
  alert_line = alert.get();
  LiveViewSink* live_view = live.get();
  sinks.push_back(std::move(alert));
  sinks.push_back(std::move(mqtt).value());
  sinks.push_back(std::move(live));
  sinks.push_back(std::move(publisher_sink));
  sinks.push_back(std::move(store));
  for (auto& sink : extra) sinks.push_back(std::move(sink));
  std::erase(sinks, nullptr);
  for (const auto& sink : sinks) spdlog::debug("output: {}", sink->name());

  if (live_view) return start_http(*live_view, **http);
  return Ok{};
}

// The live view's server, on the network loop.
Status Daemon::Impl::start_http(LiveViewSink& live, const HttpOptions& options) {
  const Config::Http& h = config.http;
  StationInfo station{.station = config.station.name,
                      .source = source_name,
                      .calibration = calibration_used.empty() ? "default rig" : calibration_used,
                      .default_rig = calibration_used.empty(),
                      .background_mode = config.silhouette.background,
                      .relearn_available = config.silhouette.background == BackgroundMode::Learn,
                      .fps = h.fps,
                      .camera_pixels = h.camera_pixels};
  HttpHandlers handlers{.metrics = [this] { return metrics(); },
                        .relearn_background = [this] {
                          if (config.silhouette.background != BackgroundMode::Learn) return false;
                          spdlog::info("http: background re-learning requested");
                          relearn_requested.store(true);
                          return true;
                        }};
  if (auto s = live.start(network->io(), options, std::move(handlers), std::move(station)); !s) return s;
  spdlog::info("live view on {}://{}:{}/ ({}; {} pictures/s at most, camera pixels {})",
               options.access.tls ? "https" : "http", options.endpoint.host, live.port(), options.access.describe(),
               h.fps, h.camera_pixels ? "shown" : "hidden");
  return Ok{};
}

}  // namespace spinewatch
