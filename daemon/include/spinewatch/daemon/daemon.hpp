#pragma once
// spinewatchd's wiring: source → pipeline → outputs (PostureSink), plus the
// control loop on the main thread (signals, sd_notify, status lines,
// reload). docs/architecture.md draws it.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "spinewatch/daemon/config.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct DaemonOverrides {  // from the command line; win over [publish]
  std::optional<std::string> listen;
  std::optional<std::string> unix_socket;
  std::optional<std::string> http;  // wins over [http] listen
};

// What a test puts in place of the station's own parts (its source, the
// estimator, outputs of its own): daemon/src/app/daemon_parts.hpp, which
// only the daemon and its tests see.
struct DaemonParts;

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
                                                DaemonOverrides overrides);
  static Result<std::unique_ptr<Daemon>> create(std::filesystem::path config_path, Config config,
                                                DaemonOverrides overrides, DaemonParts parts);
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
