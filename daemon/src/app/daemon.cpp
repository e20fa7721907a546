// The daemon's life: create() opens everything that can fail before READY,
// run() serves until a stop signal and then stops the pipeline and the
// outputs in order. The estimator thread's on_posture hands each posture,
// summary and alert to every output (PostureSink) in turn.
#include "app/daemon_impl.hpp"

#include <csignal>

#include <pthread.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "app/startup.hpp"
#include "source/recording_pair_source.hpp"
#include "spinewatch/capture/libcamera_camera.hpp"
#include "spinewatch/daemon/camera_pair_source.hpp"
#include "spinewatch/daemon/estimator_options.hpp"
#include "spinewatch/daemon/exposure_options.hpp"
#include "spinewatch/estimator/load/alert_json.hpp"

namespace spinewatch {

namespace asio = boost::asio;

Daemon::Impl::~Impl() {
  pipeline.reset();  // no more postures
  // run() has stopped the outputs and then the network loop; after a
  // failed create() the loop stops here, before the servers on it go
  // (their handlers refer to them), and the outputs go in stop order.
  if (network) network->stop();
  for (auto& sink : sinks) sink.reset();
}

// The source the configuration names (cameras, a recording, the embedded
// default), or the caller's; the rig's calibration; the recording's ground truth.
Status Daemon::Impl::open_source(DaemonParts& parts, std::unique_ptr<PairSource>& source) {
  if (parts.source) {
    plan = SourcePlan{};
    plan.kind = SourcePlan::Kind::Cameras;
    plan.why = "given by the caller: " + parts.source->describe();
    lossless = true;
  } else {
    auto planned = plan_source(config);
    if (!planned) return planned.error();
    plan = std::move(planned).value();
  }
  spdlog::info("source: {}", plan.why);
  const bool use_libcamera =
      !parts.source && plan.kind == SourcePlan::Kind::Cameras && config.cameras.source == CameraSource::Libcamera;
  if (use_libcamera && !libcamera_built())
    return Error{"cameras.source = \"libcamera\": not available in this build; use \"v4l2\""};
  if (plan.embedded)
    spdlog::info("running the embedded default: phantom recording {} replayed in a loop at its recorded rate",
                 plan.recording.string());

  auto loaded_rig = load_rig(config, plan, calibration_used);
  if (!loaded_rig) return loaded_rig.error();
  rig = *loaded_rig;

  auto opened = parts.source ? Result<std::unique_ptr<PairSource>>(std::move(parts.source))
                : use_libcamera ? open_libcamera_pair_source(config)
                : plan.kind == SourcePlan::Kind::Cameras
                    ? open_camera_pair_source(camera_pair_options(config))
                    : open_recording_pair_source(plan.recording, {.paced = plan.paced, .loop = true});
  if (!opened) return opened.error();
  source = std::move(opened).value();
  source_name = source->describe();
  if (plan.kind == SourcePlan::Kind::Recording) {
    auto score = GroundTruthScore::open(plan.recording);
    if (!score) return score.error();
    if (*score) {
      truth.emplace(std::move(**score));
      spdlog::info("{}: has ground truth: how far off the estimate is goes to /state (\"truth\") and the page",
                   plan.recording.string());
    }
  }
  if (!plan.paced) spdlog::info("replaying {} as fast as the estimator takes pairs (cameras.replay = \"fast\")", source_name);
  return workers.open_explicit_secret();
}

// The estimator with its empty scene, the exposure summaries and the alert
// rules, and the pipeline that feeds them (started by run()).
Status Daemon::Impl::start_pipeline(std::unique_ptr<PairSource> source, PostureFn estimate) {
  // Pair times are CLOCK_MONOTONIC from cameras and a paced replay (a fast
  // replay keeps the recording's): only then do summaries carry UTC times
  // and whole wall-clock intervals.
  labels.station = config.station.name;
  if (plan.kind == SourcePlan::Kind::Cameras || plan.paced) labels.utc_offset_ns = realtime_minus_monotonic_ns();
  summaries = std::make_unique<SummaryStream>(exposure_options(config), labels);
  auto rules = load_alert_rules(config);
  if (!rules) return rules.error();
  spdlog::info("alerts: {} rules{}", rules->size(), config.alerts.rules.empty() ? " (built-in)" : " from " + config.alerts.rules);
  alerts = std::make_unique<AlertMonitor>(std::move(rules).value());
  auto background = load_background(config, plan);
  if (!background) return background.error();
  auto estimator_config = load_estimator_options(config);
  if (!estimator_config) return estimator_config.error();
  estimator = std::make_shared<PostureEstimator>(rig, *estimator_config);
  if (*background)
    if (auto s = estimator->set_backgrounds((*background)->frontal.view(), (*background)->lateral.view()); !s)
      return s.error();
  if (!estimate)
    estimate = [e = estimator](const FramePair& pair) { return e->process(pair); };
  pipeline = std::make_unique<Pipeline>(
      std::move(source),
      [this, estimate = std::move(estimate)](const FramePair& pair) {
        take_pending_worker();
        if (relearn_requested.exchange(false)) estimator->relearn_background();
        return estimate(pair);
      },
      [this](const Posture& posture, const FramePair& pair) { on_posture(posture, pair); },
      PipelineOptions{.pair_queue = 4, .lossless = lossless || (plan.kind == SourcePlan::Kind::Recording && !plan.paced)});
  return Ok{};
}

// Before each pair: the worker, and the previous worker's shift closed (a
// new worker, a new shift).
void Daemon::Impl::take_pending_worker() {
  auto handover = workers.take();
  if (!handover) return;
  publish_summaries(summaries->set_worker(handover->id));  // the previous worker's, labelled as such
  labels.worker = std::move(handover->id);
  estimator->set_worker(handover->worker);
}

// Estimator thread: count, encode once, hand to every output; never blocks.
void Daemon::Impl::on_posture(const Posture& posture, const FramePair& pair) {
  counters.observe(posture);
  if (truth && !pair.camera_lost) truth->score(pair.sequence, posture);
  const EstimatorTrace trace = estimator->last_trace();
  const std::string line = encode_posture_line(posture, stream_stats());
  const PostureEvent event{posture, pair, trace, line};
  for (auto& sink : sinks) sink->on_posture(event);
  publish_summaries(summaries->add(posture));
  const bool silent = alerts_silent.load(std::memory_order_relaxed);
  for (const AlertEvent& e : alerts->update(posture)) {
    const std::string alert = encode_alert(e, labels, silent);
    for (auto& sink : sinks) sink->on_alert(e, alert);
  }
  if (!first_pair.exchange(true)) asio::post(control, [this] { on_first_pair(); });
}

void Daemon::Impl::publish_summaries(std::vector<SummaryLine> lines) {
  const std::string worker = labels.worker.value_or("");
  for (const SummaryLine& s : lines)
    for (auto& sink : sinks) sink->on_summary(s, worker);
}

DaemonMetrics Daemon::Impl::metrics() const {
  DaemonMetrics m;
  m.pipeline = pipeline ? pipeline->stats() : PipelineStats{};
  for (const auto& sink : sinks) sink->add_metrics(m);
  counters.add_metrics(m);
  m.pairs_per_s = pairs_per_s.load(std::memory_order_relaxed);
  m.uptime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (truth) m.truth = truth->stats();
  return m;
}

// The posture lines' "stats": the pipeline's, the publisher's clients, MQTT's link.
StreamStats Daemon::Impl::stream_stats() const {
  DaemonMetrics m;
  for (const auto& sink : sinks) sink->add_metrics(m);
  const PipelineStats p = pipeline->stats();
  StreamStats s{p.pairs, p.pairs_dropped, p.source.frames_lost, m.publisher.clients, m.publisher.clients_dropped};
  if (m.mqtt) {
    s.mqtt = true;
    s.mqtt_connected = m.mqtt->connected ? 1 : 0;
    s.mqtt_outbox = m.mqtt->outbox_messages;
    s.mqtt_dropped = m.mqtt->dropped();
    s.mqtt_reconnects = m.mqtt->reconnects;
  }
  return s;
}

std::string Daemon::Impl::status_text(double rate) const {
  const auto s = stream_stats();
  std::string text = fmt::format("{:.1f} pairs/s, {} pairs, {} dropped, {} frames lost, {} clients ({} dropped), {}",
                                 rate, s.pairs, s.pairs_dropped, s.frames_lost, s.clients, s.clients_dropped,
                                 to_string(counters.last_state()));
  if (trigger.configured()) text += "; trigger " + trigger.status();
  for (const auto& sink : sinks) sink->add_status(text);
  return text;
}

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

Daemon::Daemon() = default;
Daemon::~Daemon() = default;

Result<std::unique_ptr<Daemon>> Daemon::create(std::filesystem::path config_path, Config config,
                                               DaemonOverrides overrides) {
  return create(std::move(config_path), std::move(config), std::move(overrides), DaemonParts{});
}

Result<std::unique_ptr<Daemon>> Daemon::create(std::filesystem::path config_path, Config config,
                                               DaemonOverrides overrides, DaemonParts parts) {
  std::unique_ptr<Daemon> daemon(new Daemon());
  daemon->impl_ = std::make_unique<Impl>(std::move(config_path), std::move(config), std::move(overrides));
  Impl& d = *daemon->impl_;
  std::unique_ptr<PairSource> source;
  if (auto s = d.open_source(parts, source); !s) return s.error();
  if (auto s = d.open_outputs(std::move(parts.sinks)); !s) return s.error();
  d.trigger.poll();  // trigger.controller: set up now, or retried while running
  if (auto s = d.start_pipeline(std::move(source), std::move(parts.estimate)); !s) return s.error();
  return daemon;
}

void Daemon::stop() {
  Impl& d = *impl_;
  asio::post(d.control, [&d] { d.control.stop(); });
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
  d.publish_summaries(d.summaries->finish());  // the last partial interval
  // The rate at the stop is the run's mean, not the last second's (none).
  const double run_s = std::chrono::duration<double>(t0 - d.started).count();
  const auto mean_rate = [&] { return run_s > 0 ? static_cast<double>(d.stream_stats().pairs) / run_s : 0.0; };
  for (auto& sink : d.sinks) {
    // Each output hears how the run went just before it stops (the store,
    // stopping last of the station's own, records it).
    sink->on_note(NoteLevel::Info, "stopped: " + d.status_text(mean_rate()));
    sink->stop();
  }
  d.network->stop();  // both servers have closed their clients on it
  spdlog::info("stopped in {} ms after {:.1f} s; over the run: {}",
               std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0).count(),
               run_s, d.status_text(mean_rate()));
  return 0;
}

}  // namespace spinewatch
