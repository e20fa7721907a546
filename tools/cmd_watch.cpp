// spinewatch watch: a client of spinewatchd's posture stream. Prints a
// human-readable line per posture, or passes the NDJSON through (--json).
#include <cstdio>
#include <memory>
#include <optional>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "spinewatch/daemon/endpoint.hpp"

namespace spinewatch::cli {
namespace {

namespace asio = boost::asio;

std::string vec3(const nlohmann::json& v) {
  if (!v.is_array() || v.size() != 3) return "—";
  return fmt::format("({:7.1f} {:7.1f} {:7.1f})", v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
}

int severity_rank(const std::string& s) { return s == "not_acceptable" ? 2 : s == "conditional" ? 1 : 0; }

// The flag a user should see first: the most severe, the longest held.
std::string worst_flag(const nlohmann::json& posture) {
  const auto e = posture.find("ergonomics");
  if (e == posture.end() || !e->contains("flags")) return {};
  const nlohmann::json* worst = nullptr;
  for (const auto& f : (*e)["flags"]) {
    if (!worst || severity_rank(f.value("severity", "")) > severity_rank((*worst).value("severity", "")) ||
        (severity_rank(f.value("severity", "")) == severity_rank((*worst).value("severity", "")) &&
         f.value("held_s", 0.0) > (*worst).value("held_s", 0.0)))
      worst = &f;
  }
  if (!worst || severity_rank(worst->value("severity", "")) == 0) return {};
  return fmt::format("  {} {} {:.1f} ({:.1f} s)", worst->value("rule", "?"), worst->value("severity", "?"),
                     worst->value("value", 0.0), worst->value("held_s", 0.0));
}

std::string human_line(const nlohmann::json& p) {
  return fmt::format("{:>8} {:<8} neck {} waist {} latency {:>6} us{}", p.value("seq", 0ULL), p.value("state", "?"),
                     vec3(p.value("neck", nlohmann::json())), vec3(p.value("waist", nlohmann::json())),
                     p.value("latency_us", 0LL), worst_flag(p));
}

template <class Socket>
int watch(Socket& socket, bool json, long count) {
  asio::streambuf buffer(1 << 20);  // a posture line is a few kB; more is not a posture stream
  long postures = 0;
  boost::system::error_code ec;
  for (;;) {
    asio::read_until(socket, buffer, '\n', ec);
    if (ec) {
      if (ec == asio::error::eof) {
        spdlog::info("watch: the daemon closed the connection");
        return count > 0 ? 1 : 0;
      }
      spdlog::error("watch: {}", ec == asio::error::not_found ? "a line longer than 1 MiB: not a posture stream" : ec.message());
      return 1;
    }
    std::istream in(&buffer);
    std::string line;
    std::getline(in, line);
    nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object()) {
      spdlog::error("watch: not a JSON line: {:.80}", line);
      return 1;
    }
    const std::string kind = j.value("class", "");
    if (json) {
      std::fwrite(line.data(), 1, line.size(), stdout);
      std::fputc('\n', stdout);
    } else if (kind == "hello") {
      std::fprintf(stderr, "station %s, spinewatchd %s, source %s\n", j.value("station", "?").c_str(),
                   j.value("daemon_version", "?").c_str(), j.value("source", "?").c_str());
    } else if (kind == "posture") {
      std::puts(human_line(j).c_str());
    }
    std::fflush(stdout);
    if (kind == "posture" && count > 0 && ++postures >= count) return 0;
  }
}

// A refused or missing endpoint means no daemon there: say so, and how to
// point watch at one that is.
std::string connect_failure(const std::string& where, const boost::system::error_code& ec) {
  if (ec == asio::error::connection_refused || ec == boost::system::errc::no_such_file_or_directory)
    return fmt::format("watch: {}: {}: the daemon is not running there (start spinewatchd, or give the address it "
                       "listens on: --connect HOST:PORT for its --listen, --unix PATH for its --unix)",
                       where, ec.message());
  return fmt::format("watch: {}: {}", where, ec.message());
}

}  // namespace

void add_watch_command(CLI::App& app, ExitCode& exit_code) {
  struct Options {
    std::string connect = "127.0.0.1:7117";
    std::string unix_path;
    bool json = false;
    long count = 0;
  };
  auto opts = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("watch", "Show the live posture stream of spinewatchd");
  auto* connect = cmd->add_option("--connect", opts->connect, "TCP address of the daemon, HOST:PORT")->capture_default_str();
  cmd->add_option("--unix", opts->unix_path, "Unix socket of the daemon (instead of TCP)")->excludes(connect);
  cmd->add_flag("--json", opts->json, "Pass the NDJSON stream through unchanged");
  cmd->add_option("--count", opts->count, "Exit after N posture lines")->check(CLI::PositiveNumber);
  cmd->callback([opts, &exit_code] {
    asio::io_context io;
    boost::system::error_code ec;
    if (!opts->unix_path.empty()) {
      asio::local::stream_protocol::socket socket(io);
      socket.connect(asio::local::stream_protocol::endpoint(opts->unix_path), ec);
      if (ec) {
        spdlog::error("{}", connect_failure(opts->unix_path, ec));
        exit_code.value = 1;
        return;
      }
      exit_code.value = watch(socket, opts->json, opts->count);
      return;
    }
    auto endpoint = parse_listen_address(opts->connect);
    if (!endpoint) {
      spdlog::error("watch: --connect {}", endpoint.error().message);
      exit_code.value = 2;
      return;
    }
    asio::ip::tcp::resolver resolver(io);
    auto addresses = resolver.resolve(endpoint->host, std::to_string(endpoint->port), ec);
    asio::ip::tcp::socket socket(io);
    if (!ec) asio::connect(socket, addresses, ec);
    if (ec) {
      spdlog::error("{}", connect_failure(opts->connect, ec));
      exit_code.value = 1;
      return;
    }
    exit_code.value = watch(socket, opts->json, opts->count);
  });
}

}  // namespace spinewatch::cli
