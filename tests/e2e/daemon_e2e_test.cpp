// The real spinewatchd on phantom recordings: sockets, clients, signals, memory.
#include <gtest/gtest.h>

#include <fcntl.h>

#include <algorithm>
#include <functional>

#include <nlohmann/json.hpp>

#include "test_client.hpp"
#include "daemon_process.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;
using test::DaemonProcess;
using test::LineClient;

class DaemonE2E : public ::testing::Test {
 protected:
  std::filesystem::path make_recording(int frames, int empty_frames = 2) {
    const auto rec = dir / "rec";
    auto r = test::run_cli("--log-level warn phantom --subject generic --scenario flexion --frames " + std::to_string(frames) +
                           " --empty-frames " + std::to_string(empty_frames) + " --out '" + rec.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return rec;
  }
  std::filesystem::path write_config(const std::string& cameras) {
    const auto path = dir / "spinewatch.toml";
    test::write_file(path, "[station]\nname = \"e2e\"\n[cameras]\nfrontal = \"/nonexistent/video0\"\n"
                           "lateral = \"/nonexistent/video2\"\ncalibration = \"/nonexistent/cal.yaml\"\n" +
                               cameras + "[publish]\nclient_queue = 100000\n");
    return path;
  }
  test::TempDir dir;
};

TEST_F(DaemonE2E, ServesThreeClientsOnAPhantomRecordingAndStopsOnSigterm) {
  const auto rec = make_recording(30);
  const auto config = write_config("source = \"recording\"\nrecording = \"" + rec.string() + "\"\n");
  const auto port = test::free_port();
  const auto sock = dir / "p.sock";
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "127.0.0.1:" + std::to_string(port),
                        "--unix", sock.string()},
                       dir / "daemon.log");
  ASSERT_GT(daemon.pid(), 0);

  auto a = test::when_up([&] { return LineClient::tcp(port); }, daemon);
  ASSERT_TRUE(a) << daemon.log();
  auto b = test::when_up([&] { return LineClient::unix_socket(sock); }, daemon);
  ASSERT_TRUE(b) << daemon.log();
  auto silent = LineClient::tcp(port, 4096);  // connects, never reads
  auto flooder = LineClient::unix_socket(sock);

  std::vector<std::string> lines_a, lines_b;
  for (auto [client, lines] : {std::pair{&*a, &lines_a}, std::pair{&*b, &lines_b}}) {
    auto hello = client->read_line();
    ASSERT_TRUE(hello) << daemon.log();
    lines->push_back(*hello);
  }
  flooder.send_text(std::string(64 * 1024, '!'));
  // 45 lines at the recorded 30 Hz: 1.5 s.
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 45; ++i) {
    auto la = a->read_line(test::scaled(2s));
    auto lb = b->read_line(test::scaled(2s));
    ASSERT_TRUE(la && lb) << "a reader stalled at line " << i << "\n" << daemon.log();
    lines_a.push_back(*la);
    lines_b.push_back(*lb);
  }
  EXPECT_LT(std::chrono::steady_clock::now() - t0, test::scaled(4s)) << "readers were slowed down";

  const auto hello = nlohmann::json::parse(lines_a[0]);
  EXPECT_EQ(hello.at("class"), "hello");
  EXPECT_EQ(hello.at("station"), "e2e");
  EXPECT_EQ(hello.at("source"), "recording " + rec.string());
  EXPECT_EQ(lines_b[0], lines_a[0]);
  // seq rises by one per line, except where the pipeline dropped pairs it
  // could not keep up with (a slow build, the subject model's first frame):
  // every missing seq is a dropped pair, counted by the time the line after
  // the gap is written (docs/interfaces.md §3).
  for (auto* lines : {&lines_a, &lines_b}) {
    std::uint64_t previous = nlohmann::json::parse((*lines)[1]).at("seq").get<std::uint64_t>(), missing = 0;
    for (std::size_t i = 2; i < lines->size(); ++i) {
      const auto j = nlohmann::json::parse((*lines)[i]);
      if (j.at("class") == "summary") continue;  // at a whole minute (docs/exposure.md)
      EXPECT_EQ(j.at("class"), "posture");
      ASSERT_TRUE(j.contains("stats"));
      const auto seq = j.at("seq").get<std::uint64_t>();
      ASSERT_GT(seq, previous) << "seq must rise";
      missing += seq - previous - 1;
      EXPECT_LE(missing, j.at("stats").at("pairs_dropped").get<std::uint64_t>())
          << "seq " << previous << " → " << seq << ": a gap that no dropped pair accounts for";
      previous = seq;
    }
  }
  // 45 lines of a 32-frame recording: seq went on across the loop.
  test::write_file(dir / "a.ndjson", [&] {
    std::string s;
    for (auto& l : lines_a) s += l + "\n";
    return s;
  }());
  EXPECT_EQ(test::validate_ndjson(dir / "a.ndjson"), "");
  EXPECT_TRUE(flooder.wait_closed(3s)) << "a flooding client was not dropped";
  // The last posture line: a summary line at a whole minute can come last
  // and carries no "stats".
  const auto last_posture = std::find_if(lines_a.rbegin(), lines_a.rend(), [](const std::string& l) {
    return nlohmann::json::parse(l).at("class") == "posture";
  });
  ASSERT_NE(last_posture, lines_a.rend());
  EXPECT_GE(nlohmann::json::parse(*last_posture).at("stats").at("clients").get<int>(), 3);

  const auto stop_start = std::chrono::steady_clock::now();
  daemon.signal(SIGTERM);
  const auto code = daemon.wait_exit(test::scaled(2s));
  ASSERT_TRUE(code) << "no exit within 2 s of SIGTERM\n" << daemon.log();
  EXPECT_EQ(*code, 0) << daemon.log();
  std::printf("stopped %lld ms after SIGTERM\n",
              static_cast<long long>(std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - stop_start).count()));
  EXPECT_FALSE(std::filesystem::exists(sock)) << "the socket file was left behind";
  // Readers see the stream end cleanly: the lines queued while the test
  // waited for the flooder, each whole, then EOF with nothing half-sent.
  int after_stop = 0;
  while (auto l = a->read_line(1s)) {
    EXPECT_NO_THROW(nlohmann::json::parse(*l));
    ++after_stop;
  }
  EXPECT_GE(after_stop, 1) << "the lines queued at SIGTERM were not delivered";
  EXPECT_TRUE(a->saw_eof());
  EXPECT_EQ(a->pending_bytes(), 0u) << "a half line at EOF";
  const std::string log = daemon.log();
  // The flooder's drop itself (every status line says "N dropped").
  EXPECT_NE(log.find("(unix) dropped: sent a line longer than 512 bytes"), std::string::npos) << log;
  EXPECT_NE(log.find("SIGTERM"), std::string::npos) << log;
}

TEST_F(DaemonE2E, BadConfigIsOneMessageAndExitOne) {
  test::write_file(dir / "bad.toml", "[cameras]\nfps = 500\n");
  auto r = test::run_command(test::daemon_path() + " --config '" + (dir / "bad.toml").string() + "' --unix none");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bad.toml:2: cameras.fps: 500 is out of range [1, 120]"), std::string::npos) << r.output;
  auto missing = test::run_command(test::daemon_path() + " --config '" + (dir / "missing.toml").string() + "'");
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find("missing.toml: cannot open: No such file or directory"), std::string::npos) << missing.output;
  auto bad_rec = write_config("source = \"recording\"\nrecording = \"" + (dir / "nowhere").string() + "\"\n");
  auto r2 = test::run_command(test::daemon_path() + " --config '" + bad_rec.string() + "' --listen none --unix '" +
                              (dir / "s.sock").string() + "'");
  EXPECT_EQ(r2.exit_code, 1) << r2.output;
  EXPECT_NE(r2.output.find("nowhere"), std::string::npos) << r2.output;
  auto usage = test::run_command(test::daemon_path() + " --bogus");
  EXPECT_EQ(usage.exit_code, 2) << usage.output;
  auto bad_listen = test::run_command(test::daemon_path() + " --config '" + bad_rec.string() + "' --listen nonsense");
  EXPECT_EQ(bad_listen.exit_code, 1) << bad_listen.output;
}

// A stop asked for while the daemon starts (systemd stopping a unit that
// is still opening its cameras, Ctrl-C at once) is a clean stop once it
// can be taken, not the signal's default action: the signals are held
// from main()'s first line until the daemon's signal set exists.
TEST_F(DaemonE2E, SigtermWhileStartingIsACleanStop) {
  const auto config = write_config("source = \"recording\"\nrecording = \"\"\n");  // the embedded default
  for (int signo : {SIGTERM, SIGINT}) {
    DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "none", "--unix", (dir / "p.sock").string()},
                         dir / "start.log");
    ASSERT_GT(daemon.pid(), 0);
    // "starting" is logged before the source, models and sockets are set up.
    ASSERT_TRUE(test::eventually([&] { return daemon.log().find("starting") != std::string::npos; }, test::scaled(10s)))
        << daemon.log();
    daemon.signal(signo);
    EXPECT_EQ(daemon.wait_exit(test::scaled(10s)), 0) << daemon.log();
    EXPECT_NE(daemon.log().find(signo == SIGTERM ? "SIGTERM: stopping" : "SIGINT: stopping"), std::string::npos)
        << daemon.log();
    EXPECT_NE(daemon.log().find("stopped in"), std::string::npos) << daemon.log();
  }
}

// Safe by default (issue 21, docs/security.md): a TCP listener on a
// network address is refused at start while nothing authenticates its
// clients; allowed explicitly, it starts with a warning in the log and in
// every client's hello line.
TEST_F(DaemonE2E, ANetworkListenerWithoutAuthenticationIsRefusedUnlessAllowed) {
  const auto rec = make_recording(10);
  const auto config = write_config("source = \"recording\"\nrecording = \"" + rec.string() + "\"\n");
  const auto port = test::free_port();
  const std::string listen = "0.0.0.0:" + std::to_string(port);
  auto refused = test::run_command(test::daemon_path() + " --config '" + config.string() + "' --unix none --listen " + listen);
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("--listen " + listen + ": not a loopback address"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("allow_unauthenticated = true"), std::string::npos) << refused.output;

  std::string text = test::read_file(config);
  text.replace(text.find("[publish]\n"), 10, "[publish]\nallow_unauthenticated = true\n");
  test::write_file(config, text);
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", listen, "--unix", "none"}, dir / "daemon.log");
  auto client = test::when_up([&] { return LineClient::tcp(port); }, daemon);
  ASSERT_TRUE(client) << daemon.log();
  const auto line = client->read_line();
  ASSERT_TRUE(line) << daemon.log();
  const auto hello = nlohmann::json::parse(*line);
  ASSERT_TRUE(hello.contains("warnings")) << *line;
  EXPECT_NE(hello.at("warnings").at(0).get<std::string>().find("unauthenticated: tcp " + listen), std::string::npos) << *line;
  test::write_file(dir / "hello.ndjson", *line + "\n");
  EXPECT_EQ(test::validate_ndjson(dir / "hello.ndjson"), "");
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait_exit(test::scaled(2s)), 0) << daemon.log();
  EXPECT_NE(daemon.log().find("warning: unauthenticated: tcp " + listen), std::string::npos) << daemon.log();
}

TEST_F(DaemonE2E, WatchPrintsPosturesFromTheDaemon) {
  const auto rec = make_recording(10);
  const auto config = write_config("source = \"recording\"\nrecording = \"" + rec.string() + "\"\n");
  const auto sock = dir / "p.sock";
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "none", "--unix", sock.string()},
                       dir / "daemon.log");
  ASSERT_TRUE(test::when_up([&] { return LineClient::unix_socket(sock); }, daemon)) << daemon.log();
  auto json = test::run_cli("watch --unix '" + sock.string() + "' --json --count 5");
  EXPECT_EQ(json.exit_code, 0) << json.output;
  std::istringstream lines(json.output);
  int postures = 0, hellos = 0;
  for (std::string line; std::getline(lines, line);) {
    const auto j = nlohmann::json::parse(line);
    if (j.at("class") == "hello") ++hellos;
    if (j.at("class") == "posture") ++postures;
  }
  EXPECT_EQ(hellos, 1);
  EXPECT_EQ(postures, 5);
  auto human = test::run_cli("watch --unix '" + sock.string() + "' --count 3");
  EXPECT_EQ(human.exit_code, 0) << human.output;
  // run_cli merges standard error (the hello summary) into the output.
  std::istringstream human_lines(human.output);
  int posture_lines = 0;
  for (std::string line; std::getline(human_lines, line);)
    if (line.find(" latency ") != std::string::npos) ++posture_lines;
  EXPECT_EQ(posture_lines, 3) << human.output;
  EXPECT_NE(human.output.find("station e2e"), std::string::npos) << human.output;
  auto refused = test::run_cli("watch --unix '" + (dir / "nobody.sock").string() + "' --count 1");
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  daemon.signal(SIGINT);
  EXPECT_EQ(daemon.wait_exit(test::scaled(2s)), 0) << daemon.log();
}

// The next line of `client` for which `want` holds, skipping the others.
// Every line read is kept in `seen` (for the schema check).
std::optional<nlohmann::json> read_line_until(LineClient& client, const std::function<bool(const nlohmann::json&)>& want,
                                              std::chrono::milliseconds timeout, std::string& seen) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    auto line = client.read_line(std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()));
    if (!line) return std::nullopt;
    seen += *line + "\n";
    auto j = nlohmann::json::parse(*line);
    if (want(j)) return j;
  }
  return std::nullopt;
}

bool worker_is(const nlohmann::json& j, double stature, const char* stature_source, double mass, const char* mass_source) {
  if (j.at("class") != "posture" || !j.contains("worker")) return false;
  const auto& w = j.at("worker");
  return (stature == 0 || w.at("stature_mm") == stature) && w.at("stature") == stature_source && w.at("mass_kg") == mass &&
         w.at("mass") == mass_source;
}

// A known worker: the configured mass, a client's set_worker (answered to
// that client), a bad command (answered with the error; nothing changes),
// a reloaded configuration — each reaches the stream's "worker" field.
// (The phantom stands 1805 mm tall: statures far below it would be set
// aside, KnownWorker.AStatureTheCamerasContradictIsSetAsideAndSaidSo.)
TEST_F(DaemonE2E, AKnownWorkerFromConfigCommandAndReloadReachesTheStream) {
  const auto rec = make_recording(30, 10);
  const std::string cameras = "source = \"recording\"\nrecording = \"" + rec.string() + "\"\n";
  const auto config = write_config(cameras + "[subject]\nmass_kg = 70\n");
  const auto sock = dir / "p.sock";
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "none", "--unix", sock.string()},
                       dir / "daemon.log");
  auto client = test::when_up([&] { return LineClient::unix_socket(sock); }, daemon);
  ASSERT_TRUE(client) << daemon.log();
  const auto wait = test::scaled(10s);
  std::string seen;
  auto read_until = [&](LineClient& c, const std::function<bool(const nlohmann::json&)>& want, auto timeout) {
    return read_line_until(c, want, timeout, seen);
  };
  // The configured mass, the stature measured (the phantom stands).
  ASSERT_TRUE(read_until(*client, [](const auto& j) { return worker_is(j, 0, "measured", 70, "given"); }, wait))
      << daemon.log();

  ASSERT_TRUE(client->send_text("{\"command\": \"set_worker\", \"stature_mm\": 1780, \"mass_kg\": 64}\n"));
  auto reply = read_until(*client, [](const auto& j) { return j.at("class") == "reply"; }, wait);
  ASSERT_TRUE(reply) << daemon.log();
  EXPECT_EQ(reply->at("ok"), true) << reply->dump();
  EXPECT_EQ(reply->at("worker").at("stature_mm"), 1780);
  ASSERT_TRUE(read_until(*client, [](const auto& j) { return worker_is(j, 1780, "given", 64, "given"); }, wait))
      << daemon.log();

  ASSERT_TRUE(client->send_text("{\"command\": \"set_worker\", \"stature_mm\": 3000}\n"));
  reply = read_until(*client, [](const auto& j) { return j.at("class") == "reply"; }, wait);
  ASSERT_TRUE(reply) << daemon.log();
  EXPECT_EQ(reply->at("ok"), false);
  EXPECT_EQ(reply->at("error"), "stature_mm: 3000 is out of range [1000, 2300]");
  EXPECT_TRUE(read_until(*client, [](const auto& j) { return worker_is(j, 1780, "given", 64, "given"); }, wait))
      << "a rejected command changes nothing";

  std::string text = test::read_file(config);
  text.replace(text.find("mass_kg = 70\n"), 13,
               "mass_kg = 70\nstature_mm = 1760\nc7_height_mm = 1540\niliac_crest_height_mm = 1060\n");
  test::write_file(config, text);
  daemon.signal(SIGHUP);
  // The measured landmarks placed the spine and the stream says so.
  EXPECT_TRUE(read_until(
      *client,
      [](const auto& j) {
        return worker_is(j, 1760, "given", 70, "given") && j.at("worker").value("c7_height_mm", 0.0) == 1540 &&
               j.at("worker").value("iliac_crest_height_mm", 0.0) == 1060;
      },
      wait))
      << daemon.log();
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait_exit(test::scaled(2s)), 0) << daemon.log();
  test::write_file(dir / "seen.ndjson", seen);
  EXPECT_EQ(test::validate_ndjson(dir / "seen.ndjson"), "") << "posture, hello and reply lines follow their schemas";
  const std::string log = daemon.log();
  EXPECT_NE(log.find("worker set by client #1 (unix): stature 1780 mm, mass 64.0 kg"), std::string::npos) << log;
  EXPECT_NE(log.find("stature_mm: 3000 is out of range"), std::string::npos) << log;
  EXPECT_NE(log.find("worker set by the reloaded configuration: stature 1760 mm, mass 70.0 kg, C7 at 1540 mm, "
                     "iliac crest at 1060 mm"),
            std::string::npos)
      << log;
}

// sd_notify through a datagram socket standing in for systemd's.
TEST_F(DaemonE2E, NotifiesReadyStatusWatchdogAndStopping) {
  const auto rec = make_recording(10);
  const auto config = write_config("source = \"recording\"\nrecording = \"" + rec.string() + "\"\n");
  const auto notify_path = dir / "notify.sock";
  int notify = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, notify_path.c_str(), sizeof addr.sun_path - 1);
  ASSERT_EQ(::bind(notify, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  ::setenv("NOTIFY_SOCKET", notify_path.c_str(), 1);
  ::setenv("WATCHDOG_USEC", "200000", 1);
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "none", "--unix", (dir / "p.sock").string()},
                       dir / "daemon.log");
  ::unsetenv("NOTIFY_SOCKET");
  ::unsetenv("WATCHDOG_USEC");

  std::vector<std::string> messages;
  auto count = [&](const std::string& prefix) {
    return std::count_if(messages.begin(), messages.end(), [&](const std::string& m) { return m.rfind(prefix, 0) == 0; });
  };
  // Until `done` or `span`: the status goes out once a second from the
  // daemon's start, which a loaded host can delay past any fixed window.
  auto receive_until = [&](const std::function<bool()>& done, std::chrono::milliseconds span) {
    const auto deadline = std::chrono::steady_clock::now() + span;
    while (std::chrono::steady_clock::now() < deadline && !done()) {
      pollfd p{notify, POLLIN, 0};
      if (::poll(&p, 1, 20) <= 0) continue;
      char buf[4096];
      const ssize_t n = ::recv(notify, buf, sizeof buf, 0);
      if (n > 0) messages.emplace_back(buf, static_cast<std::size_t>(n));
    }
  };
  receive_until([&] { return count("STATUS=") >= 1 && count("WATCHDOG=1") >= 5; }, test::scaled(10s));
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait_exit(test::scaled(2s)), 0) << daemon.log();
  receive_until([] { return false; }, 100ms);
  ::close(notify);

  EXPECT_EQ(count("READY=1"), 1) << daemon.log();
  EXPECT_GE(count("STATUS="), 1);
  EXPECT_GE(count("WATCHDOG=1"), 5) << "expected a ping every 100 ms while pairs flow";
  EXPECT_EQ(count("STOPPING=1"), 1);
  ASSERT_FALSE(messages.empty());
  EXPECT_EQ(messages.back(), "STOPPING=1");
  const auto status = std::find_if(messages.begin(), messages.end(), [](auto& m) { return m.rfind("STATUS=", 0) == 0; });
  ASSERT_NE(status, messages.end());
  EXPECT_NE(status->find("pairs/s"), std::string::npos) << *status;
  EXPECT_NE(status->find("clients"), std::string::npos) << *status;
}

TEST_F(DaemonE2E, AMissingTriggerControllerIsLoggedAndTheDaemonRunsOn) {
  const auto rec = make_recording(10);
  const auto config = write_config("source = \"recording\"\nrecording = \"" + rec.string() +
                                   "\"\n[trigger]\ncontroller = \"/nonexistent/ttyUSB9\"\n");
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "none", "--unix", (dir / "p.sock").string()},
                       dir / "daemon.log");
  ASSERT_TRUE(test::eventually([&] { return daemon.log().find("ready") != std::string::npos; }, 10s)) << daemon.log();
  std::this_thread::sleep_for(1500ms);  // status ticks: no second message while it keeps failing
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait_exit(test::scaled(2s)), 0) << daemon.log();
  const std::string log = daemon.log();
  // One error line naming the device; the status lines carry it too.
  const std::string error = "trigger controller /nonexistent/ttyUSB9: cannot open: No such file or directory (retrying every 5 s)";
  const auto first = log.find(error);
  ASSERT_NE(first, std::string::npos) << log;
  EXPECT_EQ(log.find(error, first + 1), std::string::npos) << "logged once: " << log;
  EXPECT_NE(log.find("trigger error: trigger controller /nonexistent/ttyUSB9"), std::string::npos) << log;
}

// Under a sanitizer the run is shorter (and RSS includes shadow memory).
#if defined(__SANITIZE_ADDRESS__)
constexpr std::uint64_t kMemoryEarly = 500, kMemoryLate = 3000;
#else
constexpr std::uint64_t kMemoryEarly = 1000, kMemoryLate = 10000;
#endif

TEST_F(DaemonE2E, MemoryStaysFlatOverTenThousandPairs) {
  // Mostly an empty scene: the estimator answers "no_person" quickly, so the
  // run measures the daemon (queues, frames, sockets), not the fit's speed.
  const auto rec = make_recording(1, 40);
  const auto config = write_config("source = \"recording\"\nrecording = \"" + rec.string() + "\"\nreplay = \"fast\"\n");
  const auto sock = dir / "p.sock";
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "none", "--unix", sock.string()},
                       dir / "daemon.log");
  auto client = test::when_up([&] { return LineClient::unix_socket(sock); }, daemon);
  ASSERT_TRUE(client) << daemon.log();
  ASSERT_TRUE(client->read_line());  // hello
  long rss_1000 = -1, rss_10000 = -1;
  std::uint64_t pairs = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (rss_10000 < 0) {
    auto line = client->read_line(10s);
    ASSERT_TRUE(line) << "stream ended at " << pairs << " pairs\n" << daemon.log();
    if (line->rfind("{\"class\":\"summary\"", 0) == 0) continue;  // a minute of recording time passed
    // "pairs" in stats counts pairs taken from the source since start.
    const auto at = line->find("\"pairs\":");
    ASSERT_NE(at, std::string::npos);
    pairs = std::stoull(line->substr(at + 8));
    if (rss_1000 < 0 && pairs >= kMemoryEarly) rss_1000 = daemon.vm_rss_kb();
    if (pairs >= kMemoryLate) rss_10000 = daemon.vm_rss_kb();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("spinewatchd VmRSS at %llu pairs: %ld kB, at %llu pairs: %ld kB (%.1f s)\n",
              static_cast<unsigned long long>(kMemoryEarly), rss_1000, static_cast<unsigned long long>(kMemoryLate),
              rss_10000, seconds);
  RecordProperty("rss_kb_at_1000", static_cast<int>(rss_1000));
  RecordProperty("rss_kb_at_10000", static_cast<int>(rss_10000));
  ASSERT_GT(rss_1000, 0);
#if defined(__SANITIZE_ADDRESS__)
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait_exit(test::scaled(2s)), 0) << daemon.log();
  GTEST_SKIP() << "RSS bound not checked under AddressSanitizer (quarantine holds freed memory)";
#endif
  // One pair is 300 kB of pixels: keeping even 1 % of them would add ~30 MB.
  EXPECT_LT(rss_10000 - rss_1000, 16 * 1024) << daemon.log();
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait_exit(test::scaled(2s)), 0) << daemon.log();
}

}  // namespace
}  // namespace spinewatch
