// The real spinewatchd with TLS and authentication on its listeners
// (docs/security.md): a throwaway CA, station and client certificates made
// with the openssl CLI in the test's directory; tokens; refusals counted;
// plain-text clients on a TLS port cut without stalling the stream; secret
// files others can read refused at start.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <atomic>
#include <regex>
#include <functional>
#include <thread>

#include <nlohmann/json.hpp>

#include "test_support.hpp"
#include "test_client.hpp"
#include "http_daemon.hpp"
#include "tls_client.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;
using test::DaemonProcess;
using test::TlsClient;

constexpr const char* kTokens = "# operators\nops:ops-token-7f3a9c\nviewer:viewer-token-b21e\n";

// A CA, the station's certificate (127.0.0.1) and a client's, and a
// second CA with a client of its own that the station must not accept.
struct Pki {
  explicit Pki(const std::filesystem::path& dir) : dir(dir) {
    const std::string d = "'" + dir.string() + "'";
    const std::string ec = " -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes";
    test::write_file(dir / "san.ext", "subjectAltName=IP:127.0.0.1\n");
    const std::string script =
        "set -e; cd " + d + ";"
        "openssl req -x509" + ec + " -keyout ca.key -out ca.crt -days 2 -subj /CN=spinewatch-test-ca;"
        "openssl req -x509" + ec + " -keyout other-ca.key -out other-ca.crt -days 2 -subj /CN=another-ca;"
        "openssl req" + ec + " -keyout station.key -out station.csr -subj /CN=127.0.0.1;"
        "openssl x509 -req -in station.csr -CA ca.crt -CAkey ca.key -CAcreateserial -out station.crt -days 2 -extfile san.ext;"
        "openssl req" + ec + " -keyout client.key -out client.csr -subj /CN=client-1;"
        "openssl x509 -req -in client.csr -CA ca.crt -CAkey ca.key -CAcreateserial -out client.crt -days 2;"
        "openssl req" + ec + " -keyout intruder.key -out intruder.csr -subj /CN=intruder;"
        "openssl x509 -req -in intruder.csr -CA other-ca.crt -CAkey other-ca.key -CAcreateserial -out intruder.crt -days 2;"
        "chmod 600 *.key";
    const auto r = test::run_command("sh -c \"" + script + "\" 2>&1");
    ok = r.exit_code == 0;
    output = r.output;
    test::write_file(dir / "tokens", kTokens);
    ::chmod((dir / "tokens").c_str(), 0600);
  }
  std::filesystem::path operator/(const char* name) const { return dir / name; }
  std::filesystem::path dir;
  bool ok = false;
  std::string output;
};

std::string quoted(const std::filesystem::path& p) { return "\"" + p.string() + "\""; }

// The embedded default recording, looped; the sections' extra keys given.
std::filesystem::path write_config(const std::filesystem::path& dir, const std::string& publish, const std::string& http = "") {
  const auto path = dir / "spinewatch.toml";
  test::write_file(path, "[station]\nname = \"secure\"\n[cameras]\nsource = \"recording\"\nrecording = \"\"\n"
                         "frontal = \"/nonexistent/video0\"\nlateral = \"/nonexistent/video2\"\n"
                         "calibration = \"/nonexistent/cal.yaml\"\n[publish]\nclient_queue = 100000\n" +
                             publish + "[http]\n" + http);
  return path;
}

// A sample's value from /metrics text, or -1.
double metric(const std::string& text, const std::string& sample) {
  const auto at = text.find("\n" + sample + " ");
  return at == std::string::npos ? -1 : std::stod(text.substr(at + sample.size() + 2));
}

// One HTTPS request with Connection: close; the whole response, or "" when refused.
std::string https(std::uint16_t port, const Pki& pki, const std::string& target, const std::string& headers,
                  bool client_cert = true, bool intruder = false) {
  try {
    TlsClient c(port, pki / "ca.crt", client_cert ? pki / (intruder ? "intruder.crt" : "client.crt") : "",
                client_cert ? pki / (intruder ? "intruder.key" : "client.key") : "");
    if (!c.send("GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + headers + "Connection: close\r\n\r\n")) return "";
    return c.read_all();
  } catch (const std::exception&) {
    return "";
  }
}

class DaemonSecurity : public ::testing::Test {
 protected:
  test::TempDir dir;
};

TEST_F(DaemonSecurity, TcpStreamOverTlsNeedsAValidTokenAndPlainTextIsCutWithoutAStall) {
  const Pki pki(dir.path());
  ASSERT_TRUE(pki.ok) << pki.output;
  const auto config = write_config(dir.path(), "tls_cert = " + quoted(pki / "station.crt") + "\ntls_key = " +
                                                   quoted(pki / "station.key") + "\ntoken_file = " +
                                                   quoted(pki / "tokens") + "\nauth_timeout_s = 1.0\n");
  const auto port = test::free_port(), http_port = test::free_port();
  // Not loopback, without allow_unauthenticated: TLS and tokens make it safe.
  const std::string listen = "0.0.0.0:" + std::to_string(port);
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", listen, "--unix", "none", "--http",
                        "127.0.0.1:" + std::to_string(http_port)},
                       dir / "daemon.log");
  auto good = test::when_up([&] { return std::make_shared<TlsClient>(port, pki / "ca.crt"); }, daemon);
  ASSERT_TRUE(good) << daemon.log();
  // (Nothing comes before the auth line, not even the hello: the silent
  // client below reads the refusal as its first line.)
  ASSERT_TRUE((*good)->send("{\"command\":\"auth\",\"token\":\"viewer-token-b21e\"}\n"));
  auto reply = (*good)->read_line();
  ASSERT_TRUE(reply) << daemon.log();
  EXPECT_EQ(nlohmann::json::parse(*reply), nlohmann::json::parse(R"({"class":"reply","v":1,"command":"auth","ok":true})"));
  auto hello = (*good)->read_line();
  ASSERT_TRUE(hello);
  const auto hello_json = nlohmann::json::parse(*hello);
  EXPECT_EQ(hello_json.at("class"), "hello");
  EXPECT_FALSE(hello_json.contains("warnings")) << *hello;
  test::write_file(dir / "lines.ndjson", *reply + "\n" + *hello + "\n");
  EXPECT_EQ(test::validate_ndjson(dir / "lines.ndjson"), "");

  // The authenticated client reads postures on a thread, timing the gaps.
  std::atomic<bool> stop{false};
  std::atomic<int> postures{0};  // lines, as the HTTP misbehaviour test counts them
  std::atomic<long> longest_gap_ms{0};
  std::thread watcher([&] {
    auto last = std::chrono::steady_clock::now();
    while (!stop) {
      auto line = (*good)->read_line();
      if (!line) break;
      const auto now = std::chrono::steady_clock::now();
      ++postures;
      longest_gap_ms = std::max<long>(longest_gap_ms, std::chrono::duration_cast<std::chrono::milliseconds>(now - last).count());
      last = now;
    }
  });
  std::this_thread::sleep_for(300ms);
  const auto t0 = std::chrono::steady_clock::now();

  // A wrong token, a command instead of the auth line, silence: each answered and closed.
  auto refused_with = [&](const std::string& first_line) -> std::string {
    TlsClient c(port, pki / "ca.crt");
    if (!first_line.empty()) c.send(first_line);
    auto line = c.read_line();
    EXPECT_FALSE(c.read_line()) << "the connection stays open after a refusal";
    EXPECT_TRUE(c.closed());
    return line.value_or("");
  };
  const auto wrong = nlohmann::json::parse(refused_with("{\"command\":\"auth\",\"token\":\"ops-token-7f3a9\"}\n"));
  EXPECT_EQ(wrong.at("ok"), false);
  EXPECT_EQ(wrong.at("error"), "wrong token");
  const auto not_auth = nlohmann::json::parse(refused_with("{\"command\":\"set_worker\",\"stature_mm\":1700}\n"));
  EXPECT_NE(not_auth.at("error").get<std::string>().find("was not {\"command\":\"auth\""), std::string::npos);
  const auto silent = nlohmann::json::parse(refused_with(""));
  EXPECT_EQ(silent.at("error"), "no auth line within 1000 ms");

  // Plain-text clients on the TLS port: one speaking the protocol, one
  // speaking HTTP, some saying nothing at all; all cut, none given a line.
  std::vector<test::LineClient> plain;
  for (int i = 0; i < 12; ++i) {
    plain.push_back(test::LineClient::tcp(port));
    if (i % 3 == 0) plain.back().send_text("{\"command\":\"auth\",\"token\":\"ops-token-7f3a9c\"}\n");
    if (i % 3 == 1) plain.back().send_text("GET / HTTP/1.1\r\nHost: x\r\n\r\n");
  }
  for (auto& c : plain) {
    const auto deadline = std::chrono::steady_clock::now() + test::scaled(5s);
    std::optional<std::string> line;
    while (!c.saw_eof() && std::chrono::steady_clock::now() < deadline)
      if ((line = c.read_line(200ms))) break;
    EXPECT_FALSE(line) << "a plain-text client read: " << *line;
    EXPECT_TRUE(c.saw_eof()) << "a plain-text client was not cut";
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stop = true;
  watcher.join();
  // The stream ran at its 30 Hz throughout (as in the HTTP misbehaviour test).
  EXPECT_GE(postures.load(), static_cast<int>(seconds * 30 * 0.5 / test::kTimeScale)) << seconds << " s";
  EXPECT_LT(longest_gap_ms.load(), 500 * test::kTimeScale) << "the posture stream stalled";
  std::printf("%.1f s: %d postures, longest gap %ld ms, with 3 refused tokens and 12 plain-text clients\n", seconds,
              postures.load(), longest_gap_ms.load());

  const auto metrics = test::http_get(http_port, "/metrics");
  ASSERT_EQ(metrics.status, 200);
  EXPECT_EQ(metric(metrics.body, "spinewatch_stream_refused_total{reason=\"auth\"}"), 3) << metrics.body;
  EXPECT_EQ(metric(metrics.body, "spinewatch_stream_refused_total{reason=\"tls_handshake\"}"), 12) << metrics.body;

  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait_exit(test::scaled(5s)), 0) << daemon.log();
  const std::string log = daemon.log();
  EXPECT_EQ(log.find("unauthenticated"), std::string::npos) << log;
  EXPECT_NE(log.find("(TLS, 2 tokens)"), std::string::npos) << log;
  EXPECT_NE(log.find("authenticated as viewer"), std::string::npos) << log;  // the token's name, never the token
  EXPECT_EQ(log.find("token-7f3a9"), std::string::npos) << "a token in the log";
  EXPECT_NE(log.find("refused: wrong token"), std::string::npos) << log;
}

TEST_F(DaemonSecurity, TcpStreamWithClientCertificatesTakesTheCasClientsOnly) {
  const Pki pki(dir.path());
  ASSERT_TRUE(pki.ok) << pki.output;
  const auto config = write_config(dir.path(), "tls_cert = " + quoted(pki / "station.crt") + "\ntls_key = " +
                                                   quoted(pki / "station.key") + "\ntls_client_ca = " +
                                                   quoted(pki / "ca.crt") + "\n");
  const auto port = test::free_port();
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "0.0.0.0:" + std::to_string(port),
                        "--unix", "none"},
                       dir / "daemon.log");
  auto client = test::when_up(
      [&] { return std::make_shared<TlsClient>(port, pki / "ca.crt", pki / "client.crt", pki / "client.key"); }, daemon);
  ASSERT_TRUE(client) << daemon.log();
  auto hello = (*client)->read_line();  // no token asked for: the hello at once
  ASSERT_TRUE(hello) << daemon.log();
  EXPECT_EQ(nlohmann::json::parse(*hello).at("class"), "hello");
  EXPECT_TRUE((*client)->read_line()) << "no posture line";

  // Another CA's client, and one without a certificate: no line, cut.
  for (const bool with_cert : {true, false}) {
    std::optional<std::string> line;
    try {
      TlsClient c(port, pki / "ca.crt", with_cert ? pki / "intruder.crt" : "", with_cert ? pki / "intruder.key" : "");
      line = c.read_line();
      EXPECT_TRUE(c.closed()) << "not cut";
    } catch (const std::exception&) {  // TLS 1.2 would fail the handshake itself
    }
    EXPECT_FALSE(line) << (with_cert ? "another CA's client" : "a client without a certificate") << " read " << *line;
  }
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait_exit(test::scaled(5s)), 0) << daemon.log();
  EXPECT_NE(daemon.log().find("(TLS, client certificates)"), std::string::npos) << daemon.log();
  EXPECT_EQ(daemon.log().find("unauthenticated"), std::string::npos) << daemon.log();
}

TEST_F(DaemonSecurity, HttpOverTlsNeedsTheCasCertificateAndABearerToken) {
  const Pki pki(dir.path());
  ASSERT_TRUE(pki.ok) << pki.output;
  const auto config = write_config(dir.path(), "", "tls_cert = " + quoted(pki / "station.crt") + "\ntls_key = " +
                                                       quoted(pki / "station.key") + "\ntls_client_ca = " +
                                                       quoted(pki / "ca.crt") + "\ntoken_file = " + quoted(pki / "tokens") +
                                                       "\ntimeout_s = 2.0\n");
  const auto port = test::free_port();
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "none", "--unix",
                        (dir / "posture.sock").string(), "--http", "0.0.0.0:" + std::to_string(port)},
                       dir / "daemon.log");
  auto up = test::when_up([&] {
    if (https(port, pki, "/metrics", "").empty()) throw std::runtime_error("not yet");
    return true;
  }, daemon);
  ASSERT_TRUE(up) << daemon.log();

  const auto none = https(port, pki, "/metrics", "");
  const auto none_head = test::parse_head(none);
  EXPECT_EQ(none_head.status, 401) << none;
  EXPECT_EQ(none_head.headers.at("www-authenticate"), "Bearer realm=\"spinewatch\"");
  auto wrong_head = test::parse_head(https(port, pki, "/state", "Authorization: Bearer viewer-token-b21\r\n"));
  EXPECT_EQ(wrong_head.status, 401);
  EXPECT_NE(wrong_head.headers["www-authenticate"].find("invalid_token"), std::string::npos);
  const auto page = https(port, pki, "/", "Authorization: bearer viewer-token-b21e\r\n");
  EXPECT_EQ(test::parse_head(page).status, 200) << page.substr(0, 200);
  // Another CA's certificate, or none: no answer at all.
  EXPECT_EQ(https(port, pki, "/", "Authorization: Bearer viewer-token-b21e\r\n", true, true), "");
  EXPECT_EQ(https(port, pki, "/", "Authorization: Bearer viewer-token-b21e\r\n", false), "");
  // Plain text on the TLS port: no HTTP answer, the connection cut.
  test::HttpConnection plain(port);
  plain.send("GET /metrics HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_FALSE(plain.read_head(test::scaled(3s)));

  const auto metrics = https(port, pki, "/metrics", "Authorization: Bearer ops-token-7f3a9c\r\n");
  ASSERT_EQ(test::parse_head(metrics).status, 200) << metrics.substr(0, 300);
  EXPECT_GE(metric(metrics, "spinewatch_http_unauthorized_total"), 2) << metrics;
  EXPECT_GE(metric(metrics, "spinewatch_http_connections_dropped_total{reason=\"tls_handshake\"}"), 3) << metrics;

  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait_exit(test::scaled(5s)), 0) << daemon.log();
  EXPECT_EQ(daemon.log().find("unauthenticated"), std::string::npos) << daemon.log();
  EXPECT_NE(daemon.log().find("live view on https://0.0.0.0"), std::string::npos) << daemon.log();
}

TEST_F(DaemonSecurity, SecretsOthersCanReadAndUnprotectedNetworkBindsAreRefusedAtStart) {
  const Pki pki(dir.path());
  ASSERT_TRUE(pki.ok) << pki.output;
  const std::string tls = "tls_cert = " + quoted(pki / "station.crt") + "\ntls_key = " + quoted(pki / "station.key") + "\n";
  auto start = [&](const std::string& publish, const std::string& http, const std::string& args) {
    const auto config = write_config(dir.path(), publish, http);
    // `timeout`: a daemon that wrongly starts fails the test instead of hanging it.
    return test::run_command("timeout 30 " + test::daemon_path() + " --config '" + config.string() + "' --unix none " + args + " 2>&1");
  };
  ::chmod((pki / "tokens").c_str(), 0644);
  auto r = start(tls + "token_file = " + quoted(pki / "tokens") + "\n", "", "--listen 127.0.0.1:0");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("publish.token_file " + (pki / "tokens").string() + ": mode 0644"), std::string::npos) << r.output;
  r = start("", "token_file = " + quoted(pki / "tokens") + "\n", "--listen 127.0.0.1:0 --http 127.0.0.1:0");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("http.token_file " + (pki / "tokens").string() + ": mode 0644"), std::string::npos) << r.output;
  ::chmod((pki / "tokens").c_str(), 0600);

  ::chmod((pki / "station.key").c_str(), 0640);
  r = start(tls, "", "--listen 127.0.0.1:0");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("publish.tls_key " + (pki / "station.key").string() + ": mode 0640"), std::string::npos) << r.output;
  ::chmod((pki / "station.key").c_str(), 0600);

  // Tokens without TLS would cross the network in clear: still refused there.
  r = start("token_file = " + quoted(pki / "tokens") + "\n", "", "--listen 0.0.0.0:0");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--listen 0.0.0.0:0: not a loopback address"), std::string::npos) << r.output;
  // TLS alone encrypts but asks no one who they are: refused too.
  r = start(tls, "", "--listen 0.0.0.0:0");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("not protected (TLS)"), std::string::npos) << r.output;
  // A certificate without its key, a key that is not the certificate's.
  r = start("tls_cert = " + quoted(pki / "station.crt") + "\n", "", "--listen 127.0.0.1:0");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("publish.tls_cert: set, but publish.tls_key is not"), std::string::npos) << r.output;
  r = start("tls_cert = " + quoted(pki / "station.crt") + "\ntls_key = " + quoted(pki / "client.key") + "\n", "",
            "--listen 127.0.0.1:0");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("publish.tls_key"), std::string::npos) << r.output;
}

// One run of the daemon with a store and a Unix socket: names the worker
// `id`, waits for a summary carrying the name the station gave, stops.
struct WorkerRun {
  std::string reply_id, summary_worker, log;
  int exit_code = -1;
};
WorkerRun name_worker(const test::TempDir& dir, const std::string& id, const std::string& privacy) {
  const auto config = write_config(dir.path(), "", "");
  test::write_file(config, test::read_file(config) + "[exposure]\ninterval_s = 1\n[storage]\npath = " +
                               quoted(dir / "store.sqlite") + "\n[privacy]\n" + privacy);
  const auto sock = dir / "posture.sock";
  DaemonProcess daemon({test::daemon_path(), "--config", config.string(), "--listen", "none", "--unix", sock.string()},
                       dir / "daemon.log");
  WorkerRun run;
  auto client = test::when_up([&] { return test::LineClient::unix_socket(sock); }, daemon);
  if (client && client->send_text("{\"command\":\"set_worker\",\"id\":\"" + id + "\"}\n")) {
    const auto deadline = std::chrono::steady_clock::now() + test::scaled(20s);
    while (std::chrono::steady_clock::now() < deadline && run.summary_worker.empty()) {
      auto line = client->read_line(test::scaled(3s));
      if (!line) break;
      const auto j = nlohmann::json::parse(*line);
      if (j.at("class") == "reply") run.reply_id = j.at("worker").value("id", "");
      if (j.at("class") == "summary" && j.contains("worker")) run.summary_worker = j.at("worker");
    }
  }
  daemon.signal(SIGTERM);
  run.exit_code = daemon.wait_exit(test::scaled(5s)).value_or(-1);
  run.log = daemon.log();
  return run;
}

std::string store_bytes(const test::TempDir& dir) {
  std::string all;
  for (const char* suffix : {"", "-wal", "-journal"})
    if (std::filesystem::exists(dir / ("store.sqlite" + std::string(suffix))))
      all += test::read_file(dir / ("store.sqlite" + std::string(suffix)));
  return all;
}

TEST_F(DaemonSecurity, WorkerIdsAreStoredPublishedAndLoggedOnlyAsAPseudonymStableAcrossRestarts) {
  const std::string id = "alice.smith-17";
  const auto secret = dir / "pseudonym.key";
  const std::string privacy = "secret_file = " + quoted(secret) + "\n";
  const auto first = name_worker(dir, id, privacy);
  EXPECT_EQ(first.exit_code, 0) << first.log;
  EXPECT_TRUE(std::regex_match(first.reply_id, std::regex("w-[0-9a-f]{12}"))) << first.reply_id << "\n" << first.log;
  EXPECT_EQ(first.summary_worker, first.reply_id);
  EXPECT_EQ(first.log.find(id), std::string::npos) << "the id in the log";
  const std::string stored = store_bytes(dir);
  EXPECT_NE(stored.find(first.reply_id), std::string::npos) << "the pseudonym is not in the store";
  EXPECT_EQ(stored.find(id), std::string::npos) << "the id itself is in the store";
  // The secret was made, readable by its owner only.
  struct stat st {};
  ASSERT_EQ(::stat(secret.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  // The daemon wrote no frames: only its store, the secret and its socket
  // appear in the directory it was given (raw frames are only ever written
  // by an explicit `spinewatch record`).
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    const std::string name = entry.path().filename();
    EXPECT_TRUE(name == "spinewatch.toml" || name == "daemon.log" || name == "pseudonym.key" ||
                name.rfind("store.sqlite", 0) == 0)
        << "the daemon wrote " << name;
  }
  EXPECT_LT(stored.size(), 2u * 1024 * 1024) << "the store holds more than lines";

  // The same id, after a restart: the same pseudonym.
  const auto second = name_worker(dir, id, privacy);
  EXPECT_EQ(second.reply_id, first.reply_id) << second.log;
  // Another id: another pseudonym.
  const auto other = name_worker(dir, "bob-2", privacy);
  EXPECT_NE(other.reply_id, first.reply_id) << other.log;
  EXPECT_TRUE(std::regex_match(other.reply_id, std::regex("w-[0-9a-f]{12}"))) << other.log;
  // pseudonymise = false: the id as given, everywhere.
  const auto plain = name_worker(dir, id, "pseudonymise = false\n");
  EXPECT_EQ(plain.reply_id, id) << plain.log;
  EXPECT_EQ(plain.summary_worker, id);
  EXPECT_NE(store_bytes(dir).find(id), std::string::npos);

  // A secret others can read is refused at start, naming the key and the mode.
  ::chmod(secret.c_str(), 0644);
  const auto config = write_config(dir.path(), "", "");
  test::write_file(config, test::read_file(config) + "[privacy]\n" + privacy);
  const auto r = test::run_command("timeout 30 " + test::daemon_path() + " --config '" + config.string() +
                                   "' --listen none --unix '" + (dir / "p.sock").string() + "' 2>&1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("privacy.secret_file " + secret.string() + ": mode 0644"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace spinewatch
