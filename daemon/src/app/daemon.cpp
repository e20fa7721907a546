#include "daemon.hpp"

#include <atomic>
#include <csignal>
#include <mutex>

#include <pthread.h>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "spinewatch/capture/background_images.hpp"
#include "spinewatch/daemon/alert_output.hpp"
#include "spinewatch/capture/recording.hpp"
#include "spinewatch/daemon/camera_pair_source.hpp"
#include "spinewatch/daemon/client_command.hpp"
#include "spinewatch/daemon/config_reload.hpp"
#include "spinewatch/daemon/daemon_metrics.hpp"
#include "spinewatch/daemon/http_server.hpp"
#include "spinewatch/daemon/latency_histogram.hpp"
#include "spinewatch/daemon/live_view.hpp"
#include "spinewatch/daemon/mqtt_publisher.hpp"
#include "spinewatch/daemon/estimator_options.hpp"
#include "spinewatch/daemon/exposure_options.hpp"
#include "spinewatch/daemon/notifier.hpp"
#include "spinewatch/daemon/pipeline.hpp"
#include "spinewatch/daemon/pseudonym.hpp"
#include "spinewatch/daemon/publisher.hpp"
#include "spinewatch/daemon/recording_pair_source.hpp"
#include "spinewatch/daemon/source_plan.hpp"
#include "spinewatch/daemon/store.hpp"
#include "spinewatch/daemon/stream_lines.hpp"
#include "spinewatch/daemon/summary_stream.hpp"
#include "spinewatch/estimator/load/alert_json.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/sync/gpiod_trigger_line.hpp"
#include "spinewatch/sync/trigger_controller.hpp"

#include "../source/ground_truth.hpp"

namespace spinewatch {

namespace asio = boost::asio;

namespace {

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
    if (!is_loopback(*endpoint) && !access->safe_for_network() && !c.allow_unauthenticated)
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
  if (!is_loopback(*endpoint) && !access->safe_for_network() && !c.allow_unauthenticated)
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

// trigger.controller names the box's serial device: configure it for the
// camera rate and pulse width and start it before the pipeline starts.
Result<std::unique_ptr<sync::TriggerController>> start_trigger_controller(const Config& config) {
  auto controller = sync::TriggerController::open(config.trigger.controller);
  if (!controller) return controller.error();
  auto& c = **controller;
  auto version = c.version();
  if (!version) return version.error();
  if (auto s = c.configure({.rate_hz = config.cameras.fps, .width_us = config.trigger.pulse_us}); !s) return s.error();
  if (auto s = c.start(); !s) return s.error();
  auto status = c.status();
  if (!status) return status.error();
  spdlog::info("trigger controller {}: firmware {} (protocol {}); {}", c.device(), version->firmware,
               version->protocol, sync::describe(*status));
  return controller;
}

// [alerts] gpio_chip: the buzzer's or lamp's line. A line that cannot be
// opened is an error value here; the caller logs it once and runs on.
Result<std::unique_ptr<AlertOutput>> open_alert_output(const Config::Alerts& a) {
  auto mode = parse_alert_signal_mode(a.gpio_mode);
  if (!mode) return Error{"alerts.gpio_mode: " + mode.error().message};
  auto line = sync::open_gpiod_output(a.gpio_chip, static_cast<unsigned>(a.gpio_line), "spinewatch-alert",
                                      a.gpio_active_low);
  if (!line) return line.error();
  return std::make_unique<AlertOutput>(
      std::move(line).value(),
      AlertOutputOptions{.mode = *mode, .pulse = std::chrono::milliseconds(a.pulse_ms), .silent = a.silent},
      fmt::format("GPIO {} line {}", a.gpio_chip, a.gpio_line));
}

}  // namespace

struct Daemon::Impl {
  std::filesystem::path config_path;
  Config config;
  DaemonOverrides overrides;
  CameraRig rig;
  std::string source_name;
  std::vector<std::string> hello_warnings;  // said to every client (make_hello_line)
  // The worker a client's set_worker or a reload named, for the estimator
  // thread to take up before its next pair (declared before the publisher,
  // whose I/O thread sets it).
  std::mutex worker_mutex;
  std::optional<KnownWorker> pending_worker;
  std::optional<std::string> pending_worker_id;  // with pending_worker: the id it came with (its pseudonym)
  std::optional<Pseudonyms> pseudonyms;          // I/O thread; opened at start or at the first id
  std::unique_ptr<Publisher> publisher;
  std::unique_ptr<SummaryStream> summaries;  // estimator thread only (docs/exposure.md)
  std::unique_ptr<Store> store;              // [storage] path set (docs/storage.md)
  std::unique_ptr<AlertMonitor> alerts;      // estimator thread only
  std::unique_ptr<AlertOutput> alert_output;  // [alerts] gpio_chip, when its line could be opened
  std::uint64_t alert_output_open_failures = 0;  // 0 or 1: the line could not be opened at start
  std::atomic<bool> alerts_silent{false};     // [alerts] silent; SIGHUP may change it
  std::unique_ptr<MqttPublisher> mqtt;       // [mqtt] url set (docs/fleet.md)
  SummaryLabels labels;                      // station and UTC for summary and alert lines
  // The live view (with --http): its render thread feeds the HTTP server,
  // which runs on the publisher's I/O thread; stopped in that order, and
  // declared so that they are destroyed before the publisher.
  std::unique_ptr<LiveView> live;
  std::unique_ptr<HttpServer> http;
  std::unique_ptr<Pipeline> pipeline;
  std::shared_ptr<PostureEstimator> estimator;
  const FramePair* current_pair = nullptr;  // estimator thread: the pair being turned into a posture
  std::optional<GroundTruthScore> truth;     // a replayed recording's ground truth, when it has one
  std::atomic<bool> relearn_requested{false};  // POST /background/relearn, taken up before the next pair

  // Counters for /metrics and /state (estimator thread writes, relaxed).
  LatencyHistogram latency;
  std::array<std::atomic<std::uint64_t>, 3> postures_by_state{};
  std::atomic<std::uint64_t> tracking_lost{0};
  TrackingState previous_state = TrackingState::Lost;  // estimator thread only
  std::atomic<double> pairs_per_s{0.0};
  std::atomic<std::uint64_t> background_updates{0}, background_relearns{0}, background_bootstraps{0};
  const std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  SystemdNotifier notifier;
  std::unique_ptr<sync::TriggerController> trigger_controller;  // when trigger.controller is set
  std::string trigger_status;                                    // its last STATUS, or the error

  asio::io_context control;  // main thread: signals, timers, sd_notify
  std::atomic<bool> first_pair{false};
  std::atomic<int> last_state{static_cast<int>(TrackingState::Lost)};
  bool source_end_reported = false;

  // Status bookkeeping (control thread only).
  std::uint64_t pairs_at_last_status = 0;
  std::chrono::steady_clock::time_point last_status_time = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_log_time = std::chrono::steady_clock::now();
  std::uint64_t pairs_at_last_log = 0;
  std::uint64_t pairs_at_last_watchdog = 0;

  StreamStats stream_stats() const {
    const auto p = pipeline->stats();
    const auto c = publisher->stats();
    StreamStats s{p.pairs, p.pairs_dropped, p.source.frames_lost, c.clients, c.clients_dropped};
    if (mqtt) {
      const MqttStats q = mqtt->stats();
      s.mqtt = true;
      s.mqtt_connected = q.connected ? 1 : 0;
      s.mqtt_outbox = q.outbox_messages;
      s.mqtt_dropped = q.dropped_disconnected + q.dropped_queue_full + q.dropped_outbox_full + q.dropped_handoff_full +
                       q.dropped_outbox_error;
      s.mqtt_reconnects = q.reconnects;
    }
    return s;
  }

  std::string status_text(double rate) const {
    const auto s = stream_stats();
    std::string text = fmt::format("{:.1f} pairs/s, {} pairs, {} dropped, {} frames lost, {} clients ({} dropped), {}",
                                   rate, s.pairs, s.pairs_dropped, s.frames_lost, s.clients, s.clients_dropped,
                                   to_string(static_cast<TrackingState>(last_state.load())));
    if (!config.trigger.controller.empty()) text += "; trigger " + trigger_status;
    if (alert_output) {
      const AlertOutputStats a = alert_output->stats();
      text += fmt::format("; alert line {}{}, {} signalled, {} write errors", alert_output->name(),
                          alert_output->silent() ? " (silent)" : a.signalling ? " signalling" : "", a.signalled,
                          a.write_errors);
    } else if (alert_output_open_failures > 0) {
      text += "; alert line not open: alerts not signalled";
    }
    if (mqtt) {
      const MqttStats q = mqtt->stats();
      text += fmt::format("; mqtt {}, outbox {}, {} dropped, {} reconnects", q.connected ? "up" : "down",
                          q.outbox_messages,
                          q.dropped_disconnected + q.dropped_queue_full + q.dropped_outbox_full + q.dropped_handoff_full +
                              q.dropped_outbox_error,
                          q.reconnects);
    }
    if (store) {
      const StoreStats st = store->stats();
      text += fmt::format("; storage {} written, {} dropped, {} failed", st.written, st.dropped, st.failed);
    }
    return text;
  }

  // Control thread, once a second: one STATUS round trip (~10 ms at 115200
  // baud, at most the 500 ms reply timeout); a failure is logged when it
  // starts. A controller that could not be opened or set up (unplugged,
  // still booting) is tried again every kTriggerRetry; the daemon runs on
  // meanwhile, its status saying why there are no pairs.
  static constexpr std::chrono::seconds kTriggerRetry{5};
  std::chrono::steady_clock::time_point next_trigger_attempt{};
  void poll_trigger_controller() {
    if (config.trigger.controller.empty()) return;
    const bool was_failing = trigger_status.rfind("error", 0) == 0;
    if (!trigger_controller) {
      const auto now = std::chrono::steady_clock::now();
      if (now < next_trigger_attempt) return;
      next_trigger_attempt = now + kTriggerRetry;
      auto controller = start_trigger_controller(config);
      if (!controller) {
        if (!was_failing) spdlog::error("{} (retrying every {} s)", controller.error().message, kTriggerRetry.count());
        trigger_status = "error: " + controller.error().message;
        return;
      }
      if (was_failing) spdlog::info("trigger controller {} set up", config.trigger.controller);
      trigger_controller = std::move(controller).value();
      trigger_status.clear();
    }
    const bool failing = trigger_status.rfind("error", 0) == 0;
    auto status = trigger_controller->status();
    if (status) {
      if (failing) spdlog::info("trigger controller answers again");
      trigger_status = sync::describe(*status);
    } else {
      if (!failing) spdlog::error("{}", status.error().message);
      trigger_status = "error: " + status.error().message;
    }
  }

  static std::string describe(const KnownWorker& w) {
    std::string text = fmt::format("stature {}, mass {}", w.stature_mm ? fmt::format("{:.0f} mm", *w.stature_mm) : "not known",
                                   w.mass_kg ? fmt::format("{:.1f} kg", *w.mass_kg) : "not known");
    if (w.c7_height_mm) text += fmt::format(", C7 at {:.0f} mm", *w.c7_height_mm);
    if (w.iliac_crest_height_mm) text += fmt::format(", iliac crest at {:.0f} mm", *w.iliac_crest_height_mm);
    return text;
  }

  void set_worker(const KnownWorker& worker, std::string_view by, std::optional<std::string> id = std::nullopt) {
    spdlog::info("worker {}set by {}: {}; the subject's model is built afresh", id ? *id + " " : "", by,
                 describe(worker));
    std::lock_guard lock(worker_mutex);
    pending_worker = worker;
    pending_worker_id = std::move(id);
  }

  // On the estimator thread, before each pair: the worker, and the
  // previous worker's shift closed (a new worker, a new shift).
  std::optional<KnownWorker> take_pending_worker() {
    std::optional<std::string> id;
    std::optional<KnownWorker> worker;
    {
      std::lock_guard lock(worker_mutex);
      worker = std::exchange(pending_worker, std::nullopt);
      id = std::exchange(pending_worker_id, std::nullopt);
    }
    if (worker) {
      publish_summaries(summaries->set_worker(id));  // the previous worker's, labelled as such
      labels.worker = std::move(id);
    }
    return worker;
  }

  // On the publisher's I/O thread: one line a client sent.
  ClientInputReply on_client_line(std::string_view line, const std::string& client) {
    if (line.find_first_not_of(" \t") == std::string_view::npos) return {};
    auto command = parse_client_command(line);
    if (!command) {
      spdlog::warn("client {}: {}", client, command.error().message);
      return {rejected_reply(command.error()), false};
    }
    if (command->id) {
      // From here on only the pseudonym exists: the store, the stream, the
      // log and the reply itself carry it (docs/security.md).
      auto named = worker_name(*command->id);
      if (!named) {
        spdlog::error("client {}: set_worker refused: {}", client, named.error().message);
        return {rejected_reply(Error{"id: " + named.error().message}), false};
      }
      command->id = std::move(named).value();
    }
    set_worker(command->worker, "client " + client, command->id);
    return {accepted_reply(*command), true};
  }

  // The id as the station records it: its pseudonym unless privacy.pseudonymise = false.
  Result<std::string> worker_name(const std::string& id) {
    if (!config.privacy.pseudonymise) return id;
    if (!pseudonyms) {
      auto path = secret_path();
      if (!path) return path.error();
      auto opened = Pseudonyms::open(*path);
      if (!opened) return opened.error();
      pseudonyms = std::move(opened).value();
    }
    return pseudonyms->of(id);
  }

  Result<std::filesystem::path> secret_path() const {
    if (config.privacy.secret_file.empty()) return default_secret_path();
    return std::filesystem::path(config.privacy.secret_file);
  }

  DaemonMetrics metrics() const {
    DaemonMetrics m;
    m.pipeline = pipeline ? pipeline->stats() : PipelineStats{};
    m.publisher = publisher->stats();
    for (std::size_t i = 0; i < 3; ++i) m.postures.by_state[i] = postures_by_state[i].load(std::memory_order_relaxed);
    m.postures.tracking_lost = tracking_lost.load(std::memory_order_relaxed);
    m.background = {background_updates.load(std::memory_order_relaxed),
                    background_relearns.load(std::memory_order_relaxed),
                    background_bootstraps.load(std::memory_order_relaxed)};
    m.latency = latency.counts();
    if (mqtt) m.mqtt = mqtt->stats();
    m.pairs_per_s = pairs_per_s.load(std::memory_order_relaxed);
    m.uptime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (truth) m.truth = truth->stats();
    return m;
  }

  // On the estimator thread: encode and hand over; never blocks.
  void on_posture(const Posture& posture) {
    last_state.store(static_cast<int>(posture.state), std::memory_order_relaxed);
    latency.observe_us(posture.latency_us);
    postures_by_state[static_cast<std::size_t>(posture.state)].fetch_add(1, std::memory_order_relaxed);
    if (previous_state == TrackingState::Tracking && posture.state == TrackingState::Lost)
      tracking_lost.fetch_add(1, std::memory_order_relaxed);
    previous_state = posture.state;
    background_updates.store(posture.background.updates, std::memory_order_relaxed);
    background_relearns.store(posture.background.relearns, std::memory_order_relaxed);
    background_bootstraps.store(posture.background.bootstraps, std::memory_order_relaxed);
    if (truth && current_pair) truth->score(current_pair->sequence, posture);
    if (live && current_pair) live->offer(*current_pair, posture, estimator->last_trace());
    current_pair = nullptr;
    std::string line = encode_posture_line(posture, stream_stats());
    if (store && posture.seq % std::uint64_t(config.storage.posture_every) == 0)
      store->add_posture(posture.seq, posture.t_ns, line);
    if (mqtt) mqtt->offer_posture(posture.t_ns, line);
    publisher->publish(std::move(line));
    publish_summaries(summaries->add(posture));
    const bool silent = alerts_silent.load(std::memory_order_relaxed);
    for (const AlertEvent& e : alerts->update(posture)) {
      // The output keeps track of raised rules even when silent, so that
      // leaving silent mode signals what is still raised.
      if (alert_output) alert_output->on_event(e);
      std::string alert = encode_alert(e, labels, silent);
      if (store) store->add_alert(e.t_ns, alert);
      if (mqtt) mqtt->publish_alert(alert);
      publisher->publish(std::move(alert));
    }
    if (!first_pair.exchange(true)) asio::post(control, [this] { on_first_pair(); });
  }

  void publish_summaries(std::vector<SummaryLine> lines) {
    for (auto& s : lines) {
      if (store)
        store->add_summary(std::string(to_string(s.summary.scope)), s.summary.start_ns, s.summary.end_ns,
                           labels.worker.value_or(""), s.line);
      if (mqtt) mqtt->publish_summary(s.line);
      publisher->publish(std::move(s.line));
    }
  }

  void on_first_pair() {
    notifier.ready();
    spdlog::info("frames flow from {}; ready", source_name);
  }

  void every_second(asio::steady_timer& timer) {
    timer.expires_after(std::chrono::seconds(1));
    timer.async_wait([this, &timer](const boost::system::error_code& ec) {
      if (ec) return;
      const auto now = std::chrono::steady_clock::now();
      const std::uint64_t pairs = pipeline->stats().pairs_processed;
      const double seconds = std::chrono::duration<double>(now - last_status_time).count();
      pairs_per_s.store(seconds > 0 ? static_cast<double>(pairs - pairs_at_last_status) / seconds : 0.0);
      poll_trigger_controller();
      notifier.status(status_text(seconds > 0 ? static_cast<double>(pairs - pairs_at_last_status) / seconds : 0.0));
      pairs_at_last_status = pairs;
      last_status_time = now;
      if (now - last_log_time >= std::chrono::seconds(config.log.status_interval_s)) {
        const double log_seconds = std::chrono::duration<double>(now - last_log_time).count();
        spdlog::info("status: {}", status_text(static_cast<double>(pairs - pairs_at_last_log) / log_seconds));
        pairs_at_last_log = pairs;
        last_log_time = now;
      }
      if (pipeline->source_finished() && !source_end_reported) {
        // Cameras retry on their own and recordings loop, so this is a fault:
        // keep serving; the watchdog (no pairs, no WATCHDOG=1) restarts us.
        spdlog::error("the frame source {} ended; no more postures", source_name);
        source_end_reported = true;
      }
      every_second(timer);
    });
  }

  // WATCHDOG=1 only while pairs flow, so a stalled pipeline gets restarted.
  void watchdog(asio::steady_timer& timer, std::chrono::microseconds interval) {
    timer.expires_after(interval / 2);
    timer.async_wait([this, &timer, interval](const boost::system::error_code& ec) {
      if (ec) return;
      const std::uint64_t pairs = pipeline->stats().pairs_processed;
      if (pairs != pairs_at_last_watchdog) notifier.watchdog();
      pairs_at_last_watchdog = pairs;
      watchdog(timer, interval);
    });
  }

  void reload() {
    auto fresh = load_config(config_path);
    if (!fresh) {
      spdlog::error("reload: {}; keeping the running configuration", fresh.error().message);
      return;
    }
    std::vector<std::string> applied, need_restart;
    for (const auto& key : changed_keys(config, *fresh)) (reloadable_key(key) ? applied : need_restart).push_back(key);
    if (fresh->log.level != config.log.level)
      spdlog::default_logger()->set_level(spdlog::level::from_str(fresh->log.level));
    if (fresh->station.name != config.station.name)
      publisher->set_hello(make_hello_line(fresh->station.name, rig, source_name, hello_warnings));
    config.station = fresh->station;
    config.log = fresh->log;
    if (fresh->alerts.silent != config.alerts.silent) {
      config.alerts.silent = fresh->alerts.silent;
      alerts_silent.store(config.alerts.silent, std::memory_order_relaxed);
      if (alert_output) alert_output->set_silent(config.alerts.silent);
      spdlog::info("alerts: silent mode {}", config.alerts.silent ? "on: recorded, not signalled" : "off");
    }
    if (known_worker(fresh->subject) != known_worker(config.subject)) {
      config.subject.stature_mm = fresh->subject.stature_mm;
      config.subject.mass_kg = fresh->subject.mass_kg;
      config.subject.c7_height_mm = fresh->subject.c7_height_mm;
      config.subject.iliac_crest_height_mm = fresh->subject.iliac_crest_height_mm;
      set_worker(known_worker(config.subject), "the reloaded configuration");
    }
    if (applied.empty() && need_restart.empty()) spdlog::info("reload: {}: nothing changed", config_path.string());
    if (!applied.empty()) spdlog::info("reload: applied {}", fmt::join(applied, ", "));
    if (store && !applied.empty()) store->add_event("info", fmt::format("reload: applied {}", fmt::join(applied, ", ")));
    if (!need_restart.empty())
      spdlog::warn("reload: {} changed; restart the daemon to apply (still running with the old values)",
                   fmt::join(need_restart, ", "));
  }

  void wait_signals(asio::signal_set& signals) {
    signals.async_wait([this, &signals](const boost::system::error_code& ec, int signo) {
      if (ec) return;
      if (signo == SIGHUP) {
        spdlog::info("SIGHUP: reloading {}", config_path.string());
        reload();
        wait_signals(signals);
        return;
      }
      spdlog::info("{}: stopping", signo == SIGTERM ? "SIGTERM" : "SIGINT");
      control.stop();
    });
  }
};

namespace {
sigset_t stop_signals() {
  sigset_t set;
  sigemptyset(&set);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, s);
  return set;
}
}  // namespace

void hold_stop_signals() {
  const sigset_t set = stop_signals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

Daemon::Daemon() : impl_(std::make_unique<Impl>()) {}
Daemon::~Daemon() = default;

Result<std::unique_ptr<Daemon>> Daemon::create(std::filesystem::path config_path, Config config,
                                               DaemonOverrides overrides) {
  std::unique_ptr<Daemon> daemon(new Daemon());
  Impl& d = *daemon->impl_;
  d.config_path = std::move(config_path);
  d.config = std::move(config);
  d.overrides = std::move(overrides);

  auto plan = plan_source(d.config);
  if (!plan) return plan.error();
  spdlog::info("source: {}", plan->why);
  const bool use_libcamera = plan->kind == SourcePlan::Kind::Cameras && d.config.cameras.source == CameraSource::Libcamera;
  if (use_libcamera && !libcamera_built())
    return Error{"cameras.source = \"libcamera\": not available in this build; use \"v4l2\""};
  if (plan->embedded)
    spdlog::info("running the embedded default: phantom recording {} replayed in a loop at its recorded rate",
                 plan->recording.string());

  std::string calibration_used;
  auto rig = load_rig(d.config, *plan, calibration_used);
  if (!rig) return rig.error();
  d.rig = *rig;

  auto source = use_libcamera ? open_libcamera_pair_source(d.config)
                : plan->kind == SourcePlan::Kind::Cameras
                    ? open_camera_pair_source(camera_pair_options(d.config))
                    : open_recording_pair_source(plan->recording, {.paced = plan->paced, .loop = true});
  if (!source) return source.error();
  d.source_name = (*source)->describe();
  if (plan->kind == SourcePlan::Kind::Recording) {
    auto truth = GroundTruthScore::open(plan->recording);
    if (!truth) return truth.error();
    if (*truth) {
      d.truth.emplace(std::move(**truth));
      spdlog::info("{}: has ground truth: how far off the estimate is goes to /state (\"truth\") and the page",
                   plan->recording.string());
    }
  }
  if (!plan->paced) spdlog::info("replaying {} as fast as the estimator takes pairs (cameras.replay = \"fast\")", d.source_name);

  // A secret file set explicitly is checked now (created if absent); the
  // default one at the first worker id, so a station that names no worker
  // needs no state directory.
  if (d.config.privacy.pseudonymise && !d.config.privacy.secret_file.empty()) {
    auto opened = Pseudonyms::open(d.config.privacy.secret_file);
    if (!opened) return opened.error();
    d.pseudonyms = std::move(opened).value();
  }
  auto options = publisher_options(d.config, d.overrides);
  if (!options) return options.error();
  options->on_input = [&d](std::string_view line, const std::string& client) { return d.on_client_line(line, client); };
  if (options->tcp && !is_loopback(*options->tcp) && !options->access.safe_for_network()) {
    d.hello_warnings.push_back(fmt::format(
        "unauthenticated: tcp {}:{} serves the posture stream to anyone who can reach it (publish.allow_unauthenticated)",
        options->tcp->host, options->tcp->port));
    spdlog::warn("{}", d.hello_warnings.back());
  }
  auto http = http_options(d.config, d.overrides);
  if (!http) return http.error();
  if (*http && !is_loopback((*http)->endpoint) && !(*http)->access.safe_for_network()) {
    d.hello_warnings.push_back(fmt::format(
        "unauthenticated: http {}:{} serves the live view to anyone who can reach it (http.allow_unauthenticated)",
        (*http)->endpoint.host, (*http)->endpoint.port));
    spdlog::warn("{}", d.hello_warnings.back());
  }
  d.alerts_silent = d.config.alerts.silent;
  if (!d.config.alerts.gpio_chip.empty() && !d.config.alerts.enabled) {
    spdlog::info("alerts.enabled = false: the alert line {} line {} is not used", d.config.alerts.gpio_chip,
                 d.config.alerts.gpio_line);
  } else if (!d.config.alerts.gpio_chip.empty()) {
    auto output = open_alert_output(d.config.alerts);
    if (output) {
      d.alert_output = std::move(output).value();
      spdlog::info("alerts: signalled on {} ({}, {}{})", d.alert_output->name(), d.config.alerts.gpio_mode,
                   d.config.alerts.gpio_active_low ? "active low" : "active high",
                   d.config.alerts.silent ? "; silent for now" : "");
    } else {
      // Logged once and said to every client; the station records alerts on.
      d.alert_output_open_failures = 1;
      d.hello_warnings.push_back(fmt::format("alerts not signalled: {} (alerts.gpio_chip)", output.error().message));
      spdlog::error("{}", d.hello_warnings.back());
    }
  }
  auto publisher =
      Publisher::start(*options, make_hello_line(d.config.station.name, d.rig, d.source_name, d.hello_warnings));
  if (!publisher) return publisher.error();
  d.publisher = std::move(publisher).value();
  if (options->tcp)
    spdlog::info("publishing on tcp {}:{} ({})", options->tcp->host, d.publisher->tcp_port(), options->access.describe());
  if (options->unix_socket) spdlog::info("publishing on unix socket {}", options->unix_socket->string());

  d.poll_trigger_controller();  // trigger.controller: set up now, or retried while running

  auto background = load_background(d.config, *plan);
  if (!background) return background.error();
  auto estimator_config = load_estimator_options(d.config);
  if (!estimator_config) return estimator_config.error();
  auto estimator = std::make_shared<PostureEstimator>(d.rig, *estimator_config);
  // Pair times are CLOCK_MONOTONIC from cameras and a paced replay (a fast
  // replay keeps the recording's): only then do summaries carry UTC times
  // and whole wall-clock intervals.
  SummaryLabels labels;
  labels.station = d.config.station.name;
  if (plan->kind == SourcePlan::Kind::Cameras || plan->paced) labels.utc_offset_ns = realtime_minus_monotonic_ns();
  d.labels = labels;
  d.summaries = std::make_unique<SummaryStream>(exposure_options(d.config), std::move(labels));
  auto rules = load_alert_rules(d.config);
  if (!rules) return rules.error();
  spdlog::info("alerts: {} rules{}", rules->size(),
               d.config.alerts.rules.empty() ? " (built-in)" : " from " + d.config.alerts.rules);
  d.alerts = std::make_unique<AlertMonitor>(std::move(rules).value());
  if (!d.config.storage.path.empty()) {
    d.store = std::make_unique<Store>(store_options(d.config));
    d.store->add_event("info", fmt::format("started: source {}", d.source_name));
    if (d.alert_output_open_failures > 0) d.store->add_event("error", d.hello_warnings.back());
  }
  auto mqtt = mqtt_options(d.config);
  if (!mqtt) return mqtt.error();
  if (*mqtt) {
    auto started = MqttPublisher::start(std::move(**mqtt));
    if (!started) return started.error();
    d.mqtt = std::move(started).value();
    spdlog::info("mqtt: publishing to {} under {}* (postures at {} Hz at most, QoS {}; outbox {})", d.config.mqtt.url,
                 d.mqtt->topic(""), d.config.mqtt.posture_rate_hz, d.config.mqtt.qos,
                 d.config.mqtt.outbox_path.empty() ? "in the state directory" : d.config.mqtt.outbox_path);
  }
  if (*background)
    if (auto s = estimator->set_backgrounds((*background)->frontal.view(), (*background)->lateral.view()); !s)
      return s.error();
  d.estimator = estimator;

  if (*http) {
    const Config::Http& h = d.config.http;
    d.live = std::make_unique<LiveView>(
        d.rig, LiveViewOptions{.fps = h.fps, .camera_pixels = h.camera_pixels, .note = d.config.station.name},
        [&d](std::shared_ptr<const LiveFrame> frame) {
          if (d.http) d.http->on_frame(std::move(frame));
        });
    StationInfo station{.station = d.config.station.name,
                        .source = d.source_name,
                        .calibration = calibration_used.empty() ? "default rig" : calibration_used,
                        .default_rig = calibration_used.empty(),
                        .background_mode = std::string(to_string(d.config.silhouette.background)),
                        .relearn_available = d.config.silhouette.background == BackgroundMode::Learn,
                        .fps = h.fps,
                        .camera_pixels = h.camera_pixels};
    HttpHandlers handlers{.metrics = [&d] { return d.metrics(); },
                          .relearn_background = [&d] {
                            if (d.config.silhouette.background != BackgroundMode::Learn) return false;
                            spdlog::info("http: background re-learning requested");
                            d.relearn_requested.store(true);
                            return true;
                          }};
    auto server = HttpServer::start(d.publisher->io_context(), **http, std::move(handlers), std::move(station), *d.live);
    if (!server) return server.error();
    d.http = std::move(server).value();
    spdlog::info("live view on {}://{}:{}/ ({}; {} pictures/s at most, camera pixels {})",
                 (*http)->access.tls ? "https" : "http", (*http)->endpoint.host, d.http->port(),
                 (*http)->access.describe(), h.fps, h.camera_pixels ? "shown" : "hidden");
  }

  d.pipeline = std::make_unique<Pipeline>(
      std::move(source).value(),
      [estimator, &d](const FramePair& pair) {
        if (auto worker = d.take_pending_worker()) estimator->set_worker(*worker);
        if (d.relearn_requested.exchange(false)) estimator->relearn_background();
        d.current_pair = &pair;  // for the live view, in on_posture right after
        return estimator->process(pair);
      },
      [&d](const Posture& posture) { d.on_posture(posture); },
      PipelineOptions{.pair_queue = 4, .lossless = plan->kind == SourcePlan::Kind::Recording && !plan->paced});
  return daemon;
}

int Daemon::run() {
  Impl& d = *impl_;
  asio::signal_set signals(d.control, SIGINT, SIGTERM, SIGHUP);
  d.wait_signals(signals);
  // The set's handlers are installed: a signal held since start-up is
  // delivered now, to this thread (the others keep the mask), and only
  // queues the stop for the loop below.
  const sigset_t held = stop_signals();
  pthread_sigmask(SIG_UNBLOCK, &held, nullptr);
  asio::steady_timer status_timer(d.control), watchdog_timer(d.control);
  d.every_second(status_timer);
  if (auto interval = SystemdNotifier::watchdog_interval()) {
    spdlog::info("systemd watchdog: every {} ms while pairs flow", interval->count() / 2000);
    d.watchdog(watchdog_timer, *interval);
  }
  d.pipeline->start();
  d.control.run();

  d.notifier.stopping();
  const auto t0 = std::chrono::steady_clock::now();
  d.pipeline->stop();
  if (d.alert_output) d.alert_output->stop();  // the buzzer or lamp off before anything else
  d.publish_summaries(d.summaries->finish());  // the last partial interval
  if (d.mqtt) d.mqtt->stop();                  // sends what it can, says "offline"
  if (d.http) d.http->stop();
  if (d.live) d.live->stop();
  d.publisher->stop();
  // The rate at the stop is the run's mean, not the last second's (none).
  const double run_s = std::chrono::duration<double>(t0 - d.started).count();
  const double mean_rate = run_s > 0 ? static_cast<double>(d.stream_stats().pairs) / run_s : 0.0;
  if (d.store) {
    d.store->add_event("info", "stopped: " + d.status_text(mean_rate));
    d.store->stop();
  }
  spdlog::info("stopped in {} ms after {:.1f} s; over the run: {}",
               std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0).count(),
               run_s, d.status_text(mean_rate));
  return 0;
}

}  // namespace spinewatch
