#pragma once
// spinewatchd's wiring: source → pipeline → publisher, plus the control
// loop on the main thread (signals, sd_notify, status lines, reload).
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
  ~Daemon();
  // Runs until SIGTERM or SIGINT (one held since hold_stop_signals()
  // included); the exit code.
  int run();

 private:
  Daemon();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinewatch
