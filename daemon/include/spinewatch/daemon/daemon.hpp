#pragma once
// spinewatchd's wiring: source → pipeline → outputs (PostureSink), plus the
// control loop on the main thread (signals, sd_notify, status lines,
// reload). docs/architecture.md draws it.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/pair_source.hpp"
#include "spinewatch/daemon/pipeline.hpp"
#include "spinewatch/daemon/posture_sink.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct DaemonOverrides {  // from the command line; win over [publish]
  std::optional<std::string> listen;
  std::optional<std::string> unix_socket;
  std::optional<std::string> http;  // wins over [http] listen
};

// What a caller (a test, an embedding program) puts in place of the
// station's own parts. Empty: all the station's own, as the configuration says.
struct DaemonParts {
  // Instead of the cameras or recording [cameras] names; it is read
  // lossless, as a fast replay: it waits for the estimator, no pair dropped.
  std::unique_ptr<PairSource> source;
  PostureFn estimate;                  // instead of the posture estimator
  // Outputs after the station's own (publisher, storage, MQTT, alert line,
  // live view); they stop last, in this order.
  std::vector<std::unique_ptr<PostureSink>> sinks;
};

// Called first in main(): SIGINT, SIGTERM and SIGHUP are held pending
// until run() has its signal set. Their default action would otherwise end
// a daemon signalled while it starts (opening cameras, loading models)
// without a clean stop, and every thread started meanwhile inherits the
// mask, so none of them takes the signal either.
void hold_stop_signals();

class Daemon {
 public:
  // Everything that can fail before READY: calibration, source, sockets.
  static Result<std::unique_ptr<Daemon>> create(std::filesystem::path config_path, Config config,
                                                DaemonOverrides overrides, DaemonParts parts = {});
  ~Daemon();
  // Runs until SIGTERM or SIGINT (one held since hold_stop_signals()
  // included) or stop(); the exit code.
  int run();
  // Any thread: run() stops its outputs and returns, as on SIGTERM.
  void stop();

 private:
  Daemon();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinewatch
