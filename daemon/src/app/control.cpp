// The main thread's loop: SIGHUP reloads, SIGTERM/SIGINT stop; once a
// second the status (sd_notify, the log every log.status_interval_s) and
// the trigger box; the systemd watchdog while pairs flow.
#include <csignal>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include "app/daemon_impl.hpp"
#include "ops/config_reload.hpp"
#include "publish/stream_lines.hpp"
#include "spinewatch/daemon/estimator_options.hpp"

namespace spinewatch {

namespace asio = boost::asio;

void Daemon::Impl::on_first_pair() {
  notifier.ready();
  spdlog::info("frames flow from {}; ready", source_name);
}

void Daemon::Impl::every_second(asio::steady_timer& timer) {
  timer.expires_after(std::chrono::seconds(1));
  timer.async_wait([this, &timer](const boost::system::error_code& ec) {
    if (ec) return;
    const auto now = std::chrono::steady_clock::now();
    const std::uint64_t pairs = pipeline->stats().pairs_processed;
    const double seconds = std::chrono::duration<double>(now - last_status_time).count();
    pairs_per_s.store(seconds > 0 ? static_cast<double>(pairs - pairs_at_last_status) / seconds : 0.0);
    trigger.poll();
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
void Daemon::Impl::watchdog(asio::steady_timer& timer, std::chrono::microseconds interval) {
  timer.expires_after(interval / 2);
  timer.async_wait([this, &timer, interval](const boost::system::error_code& ec) {
    if (ec) return;
    const std::uint64_t pairs = pipeline->stats().pairs_processed;
    if (pairs != pairs_at_last_watchdog) notifier.watchdog();
    pairs_at_last_watchdog = pairs;
    watchdog(timer, interval);
  });
}

void Daemon::Impl::reload() {
  auto fresh = load_config(config_path);
  if (!fresh) {
    spdlog::error("reload: {}; keeping the running configuration", fresh.error().message);
    return;
  }
  std::vector<std::string> applied, need_restart;
  for (const auto& key : changed_keys(config, *fresh)) (reloadable_key(key) ? applied : need_restart).push_back(key);
  if (fresh->log.level != config.log.level) set_log_level(fresh->log.level);
  if (fresh->station.name != config.station.name)
    publisher->set_hello(make_hello_line(fresh->station.name, rig, source_name, hello_warnings));
  config.station = fresh->station;
  config.log = fresh->log;
  if (fresh->alerts.silent != config.alerts.silent) {
    config.alerts.silent = fresh->alerts.silent;
    alerts_silent.store(config.alerts.silent, std::memory_order_relaxed);
    if (alert_line) alert_line->set_silent(config.alerts.silent);
    spdlog::info("alerts: silent mode {}", config.alerts.silent ? "on: recorded, not signalled" : "off");
  }
  if (known_worker(fresh->subject) != known_worker(config.subject)) {
    config.subject.stature_mm = fresh->subject.stature_mm;
    config.subject.mass_kg = fresh->subject.mass_kg;
    config.subject.c7_height_mm = fresh->subject.c7_height_mm;
    config.subject.iliac_crest_height_mm = fresh->subject.iliac_crest_height_mm;
    workers.set(known_worker(config.subject), "the reloaded configuration");
  }
  if (applied.empty() && need_restart.empty()) spdlog::info("reload: {}: nothing changed", config_path.string());
  if (!applied.empty()) spdlog::info("reload: applied {}", fmt::join(applied, ", "));
  if (!applied.empty())
    for (auto& sink : sinks) sink->on_note(NoteLevel::Info, fmt::format("reload: applied {}", fmt::join(applied, ", ")));
  if (!need_restart.empty())
    spdlog::warn("reload: {} changed; restart the daemon to apply (still running with the old values)",
                 fmt::join(need_restart, ", "));
}

void Daemon::Impl::wait_signals(asio::signal_set& signals) {
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

}  // namespace spinewatch
