// spinewatchd: the posture station daemon (docs/interfaces.md §4–§6).
#include <cstdio>
#include <filesystem>
#include <string_view>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "spinewatch/daemon/daemon.hpp"
#include "spinewatch/daemon/logging.hpp"
#include "spinewatch/version.hpp"

namespace spinewatch {
// config/spinewatch.toml, embedded (daemon/CMakeLists.txt).
std::string_view annotated_config();
}  // namespace spinewatch

int main(int argc, char** argv) {
  using namespace spinewatch;
  hold_stop_signals();  // before any thread exists
  CLI::App app{"spinewatchd: spine posture daemon; publishes the posture stream on its sockets", "spinewatchd"};
  app.set_version_flag("--version", kVersion);
  const std::string default_config = "/etc/spinewatch/spinewatch.toml";
  std::string config_path = default_config;
  std::string listen, unix_socket, http;
  app.add_option("--config", config_path, "TOML configuration file")->capture_default_str();
  bool print_config = false;
  app.add_flag("--print-config", print_config,
               "Print the annotated configuration (every key at its default) and exit: "
               "spinewatchd --print-config > spinewatch.toml");
  auto* listen_opt = app.add_option("--listen", listen, "TCP address HOST:PORT, or none (overrides publish.listen)");
  auto* unix_opt = app.add_option("--unix", unix_socket, "Unix socket path, or none (overrides publish.unix_socket)");
  auto* http_opt = app.add_option("--http", http, "live view and metrics at HOST:PORT, or none (overrides http.listen)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }

  if (print_config) {
    std::fwrite(annotated_config().data(), 1, annotated_config().size(), stdout);
    return std::fflush(stdout) == 0 ? 0 : 1;
  }
  setup_logging(LogLevel::Info);
  auto config = load_config(config_path);
  if (!config) {
    // Started by hand without --config on a machine where nothing is installed: say where one is.
    if (config_path == default_config && !std::filesystem::exists(config_path))
      spdlog::error("{}: no such file; give --config FILE. The annotated configuration, every key at its default: "
                    "spinewatchd --print-config > spinewatch.toml writes it (the same as config/spinewatch.toml in "
                    "the source tree; cmake --install puts it at PREFIX/etc/spinewatch/spinewatch.toml; docs/daemon.md)",
                    config_path);
    else
      spdlog::error("{}", config.error().message);
    return 1;
  }
  setup_logging(config->log.level);
  spdlog::info("spinewatchd {} starting, station \"{}\", config {}", kVersion, config->station.name, config_path);

  DaemonOverrides overrides;
  if (*listen_opt) overrides.listen = listen;
  if (*unix_opt) overrides.unix_socket = unix_socket;
  if (*http_opt) overrides.http = http;
  auto daemon = Daemon::create(config_path, std::move(config).value(), overrides);
  if (!daemon) {
    spdlog::error("{}", daemon.error().message);
    return 1;
  }
  return (*daemon)->run();
}
