#pragma once
// The daemon's state, shared by its files: daemon.cpp (create, run, the
// estimator thread's on_posture), outputs.cpp (the sinks, listed) and
// control.cpp (the main thread's loop: signals, status, watchdog, reload).
//
// Threads: the main thread runs `control`; the pipeline's source and
// estimator threads; the network loop's I/O thread (clients, HTTP); each
// output's own writer thread. Each member says who writes it.
#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>

#include "app/daemon_parts.hpp"
#include "app/posture_counters.hpp"
#include "app/trigger_monitor.hpp"
#include "app/worker_desk.hpp"
#include "net/network_loop.hpp"
#include "ops/notifier.hpp"
#include "outputs/sinks.hpp"
#include "source/ground_truth.hpp"
#include "source/source_plan.hpp"
#include "spinewatch/daemon/daemon.hpp"
#include "spinewatch/estimator/load/alerts.hpp"
#include "spinewatch/estimator/pipeline.hpp"

namespace spinewatch {

struct Daemon::Impl {
  Impl(std::filesystem::path path, Config c, DaemonOverrides o)
      : config_path(std::move(path)), config(std::move(c)), overrides(std::move(o)), workers(config.privacy),
        trigger(config) {}
  ~Impl();

  // create()'s steps, in order.
  Status open_source(DaemonParts& parts, std::unique_ptr<PairSource>& source);
  Status open_outputs(std::vector<std::unique_ptr<PostureSink>> extra);
  Status start_http(LiveViewSink& live, const HttpOptions& options);
  Status start_pipeline(std::unique_ptr<PairSource> source, PostureFn estimate);

  // Estimator thread.
  void on_posture(const Posture& posture, const FramePair& pair);
  void publish_summaries(std::vector<SummaryLine> lines);
  void take_pending_worker();

  // Any thread: the outputs' and the pipeline's counters.
  DaemonMetrics metrics() const;
  StreamStats stream_stats() const;
  std::string status_text(double rate) const;

  // Main thread (control.cpp).
  void on_first_pair();
  void every_second(boost::asio::steady_timer& timer);
  void watchdog(boost::asio::steady_timer& timer, std::chrono::microseconds interval);
  void reload();
  void wait_signals(boost::asio::signal_set& signals);

  std::filesystem::path config_path;
  Config config;  // main thread after start (reload)
  DaemonOverrides overrides;
  SourcePlan plan;
  bool lossless = false;  // the source waits for the estimator: a fast replay, or a caller's source
  CameraRig rig;
  std::string calibration_used;  // "" for the default rig
  std::string source_name;
  std::vector<std::string> hello_warnings;  // said to every client (make_hello_line)
  WorkerDesk workers;                       // declared before the outputs, whose threads reach it

  // Both servers' I/O thread (the publisher's clients, HTTP). Declared
  // before the outputs: stopped after them, destroyed after them.
  std::unique_ptr<net::NetworkLoop> network;
  // The outputs, in the order they stop (outputs.cpp lists them). Written
  // during create() only; every thread reads.
  std::vector<std::unique_ptr<PostureSink>> sinks;
  Publisher* publisher = nullptr;       // in `sinks`: the hello on reload
  AlertLineSink* alert_line = nullptr;  // in `sinks` with [alerts] gpio_chip: silent mode on reload

  // Estimator thread only, after create().
  std::unique_ptr<SummaryStream> summaries;  // docs/exposure.md
  std::unique_ptr<AlertMonitor> alerts;
  SummaryLabels labels;  // station, UTC and worker for summary and alert lines
  std::atomic<bool> alerts_silent{false};  // [alerts] silent; SIGHUP may change it
  std::shared_ptr<PostureEstimator> estimator;
  std::optional<GroundTruthScore> truth;        // a replayed recording's ground truth, when it has one
  std::atomic<bool> relearn_requested{false};  // POST /background/relearn, taken up before the next pair
  PostureCounters counters;
  std::unique_ptr<Pipeline> pipeline;  // declared after what its threads use: stopped first

  // Main thread.
  const std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  SystemdNotifier notifier;
  TriggerMonitor trigger;
  boost::asio::io_context control;  // signals, timers, sd_notify
  std::atomic<bool> first_pair{false};
  std::atomic<double> pairs_per_s{0.0};
  bool source_end_reported = false;
  std::uint64_t pairs_at_last_status = 0;
  std::chrono::steady_clock::time_point last_status_time = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_log_time = std::chrono::steady_clock::now();
  std::uint64_t pairs_at_last_log = 0;
  std::uint64_t pairs_at_last_watchdog = 0;
};

}  // namespace spinewatch
