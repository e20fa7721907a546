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

class Daemon {
 public:
  // Everything that can fail before READY: calibration, source, sockets.
  static Result<std::unique_ptr<Daemon>> create(std::filesystem::path config_path, Config config,
                                                DaemonOverrides overrides);
  ~Daemon();
  // Runs until SIGTERM or SIGINT; the exit code.
  int run();

 private:
  Daemon();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinewatch
