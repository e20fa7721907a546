// spinewatchd and a real MQTT broker (docs/fleet.md; docs/interfaces.md §7):
// Debian's mosquitto on loopback at a free port, a libmosquitto subscriber.
// The documented topics carry schema-valid payloads; status turns offline
// when the daemon is SIGKILLed; a 30 s broker outage loses no summary or
// alert; a restart delivers what waited in the outbox (bounded); TLS with
// a test CA works and a wrong CA fails; a wrong password is refused,
// counted, logged, and the daemon runs on. Skipped, with the reason, where
// mosquitto is not installed.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>

#include <atomic>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "http_client.hpp"
#include "test_client.hpp"
#include "daemon_process.hpp"
#include "mqtt_broker.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;
using test::DaemonProcess;
using test::LineClient;
using test::MqttMessage;

// An alert rule a flexion recording raises and clears again within seconds.
constexpr const char* kQuickRules =
    "[[rule]]\nname = \"bent\"\ninclination_above_deg = 8.0\nhold_s = 0.2\nhysteresis_deg = 2.0\nmin_interval_s = 0.5\n";

class DaemonMqtt : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    recording_dir_ = new test::TempDir();
    auto r = test::run_cli("--log-level warn phantom --subject generic --scenario flexion --frames 60 --empty-frames 2 --out '" +
                           (*recording_dir_ / "rec").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    test::write_file(*recording_dir_ / "rules.toml", kQuickRules);
  }
  static void TearDownTestSuite() {
    delete recording_dir_;
    recording_dir_ = nullptr;
  }
  void SetUp() override {
    if (!test::mosquitto_available()) GTEST_SKIP() << test::kMosquitto << " is not installed (Debian package mosquitto)";
  }

  // A configuration replaying the flexion recording with 1 s summaries,
  // quick alerts, and `mqtt` as the [mqtt] section.
  std::filesystem::path config(const std::string& station, const std::string& mqtt, const std::string& extra = "") {
    std::string file = station;
    for (char& c : file)
      if (c == '/' || c == '#') c = '-';
    const auto path = dir_ / (file + ".toml");
    test::write_file(path, "[station]\nname = \"" + station + "\"\n[cameras]\nsource = \"recording\"\nrecording = \"" +
                               (*recording_dir_ / "rec").string() +
                               "\"\ncalibration = \"/nonexistent/cal.yaml\"\n[publish]\nclient_queue = 100000\n"
                               "[exposure]\ninterval_s = 1\n[alerts]\nrules = \"" +
                               (*recording_dir_ / "rules.toml").string() + "\"\n" + extra + "[mqtt]\n" + mqtt);
    return path;
  }
  std::unique_ptr<DaemonProcess> daemon(const std::string& station, const std::filesystem::path& config,
                                        std::vector<std::string> more = {}) {
    std::vector<std::string> args{test::daemon_path(), "--config", config.string(), "--listen", "none", "--unix",
                                  (dir_ / (station + ".sock")).string()};
    args.insert(args.end(), more.begin(), more.end());
    return std::make_unique<DaemonProcess>(args, dir_ / (station + ".log"));
  }
  std::optional<LineClient> connect(const std::string& station) {
    for (auto deadline = std::chrono::steady_clock::now() + test::scaled(15s); std::chrono::steady_clock::now() < deadline;) {
      try {
        return LineClient::unix_socket(dir_ / (station + ".sock"));
      } catch (const std::exception&) {
        std::this_thread::sleep_for(20ms);
      }
    }
    return std::nullopt;
  }
  static bool wait_log(DaemonProcess& d, const std::string& text, std::chrono::milliseconds timeout) {
    for (auto deadline = std::chrono::steady_clock::now() + timeout; std::chrono::steady_clock::now() < deadline;) {
      if (d.log().find(text) != std::string::npos) return true;
      std::this_thread::sleep_for(50ms);
    }
    return false;
  }
  static int count(const std::vector<MqttMessage>& ms, const std::string& topic) {
    int n = 0;
    for (auto& m : ms) n += m.topic == topic;
    return n;
  }
  static bool status_is(const std::vector<MqttMessage>& ms, const std::string& station, const std::string& value) {
    auto last = test::last_on(ms, "spinewatch/" + station + "/status");
    return last && last->payload == value;
  }
  std::string anonymous_listener(std::uint16_t port) {
    return "listener " + std::to_string(port) + " 127.0.0.1\nallow_anonymous true\n";
  }

  static test::TempDir* recording_dir_;
  test::TempDir dir_;
};
test::TempDir* DaemonMqtt::recording_dir_ = nullptr;

TEST_F(DaemonMqtt, DocumentedTopicsCarrySchemaValidPayloadsAndStatusTurnsOfflineOnSigkill) {
  const std::uint16_t port = test::free_port();
  test::MosquittoBroker broker(dir_ / "broker", anonymous_listener(port), {port});
  ASSERT_TRUE(broker.start()) << broker.log();
  test::MqttSubscriber sub({.port = port});
  ASSERT_TRUE(sub.wait_subscribed(test::scaled(5s)));
  // "hall/B#1": the topic level is "hall_B_1" (docs/fleet.md).
  auto d = daemon("hall-B-1", config("hall/B#1", "url = \"mqtt://127.0.0.1:" + std::to_string(port) +
                                                     "\"\nposture_rate_hz = 5\nqos = 1\noutbox_path = \"" +
                                                     (dir_ / "outbox.db").string() + "\"\n"));
  const std::string t = "spinewatch/hall_B_1/";
  ASSERT_TRUE(sub.wait_for(test::scaled(30s), [&](const std::vector<MqttMessage>& ms) {
    return count(ms, t + "posture") >= 5 && count(ms, t + "summary") >= 4 && count(ms, t + "alert") >= 1 &&
           status_is(ms, "hall_B_1", "online");
  })) << d->log() << broker.log();
  std::string lines;
  // A posture encoded before the broker's CONNACK says the link is down
  // and is still delivered (QoS 1, queued): the stream says 1 from the
  // first posture after the link came up, and never 0 after that.
  bool link_seen_up = false;
  for (const auto& m : sub.messages()) {
    if (m.topic == t + "status") continue;
    EXPECT_TRUE(m.topic == t + "posture" || m.topic == t + "summary" || m.topic == t + "alert") << m.topic;
    EXPECT_EQ(m.payload.find('\n'), std::string::npos) << "one JSON line per message";
    auto j = nlohmann::json::parse(m.payload);
    const std::string kind = j.value("class", "posture");
    EXPECT_EQ(m.topic, t + kind);
    if (m.topic == t + "posture") {
      EXPECT_EQ(m.qos, 1) << "mqtt.qos = 1";
      if (j.at("stats").at("mqtt_connected") == 1)
        link_seen_up = true;
      else
        EXPECT_FALSE(link_seen_up) << "a posture said the link was down after it was up: " << m.payload;
    } else {
      EXPECT_EQ(m.qos, 1) << "summaries and alerts at QoS 1";
    }
    lines += m.payload + "\n";
  }
  EXPECT_TRUE(link_seen_up) << "no posture's stats said the MQTT link was up";
  test::write_file(dir_ / "mqtt.ndjson", lines);
  EXPECT_EQ(test::validate_ndjson(dir_ / "mqtt.ndjson"), "");
  // Decimated to 5 Hz at most from a 30 Hz stream (first to last posture
  // time). The decimator keeps a 200 ms schedule (and takes a posture 5 ms
  // early): the first posture published may come up to a period after its
  // slot when pairs are late (a loaded machine, ASan), and the rest keep the
  // slots, so over n postures the span is at least (n - 1) periods less one
  // period and the slack. Undecimated, 30 Hz would be six times as many.
  std::vector<std::int64_t> times;
  for (const auto& m : sub.on(t + "posture")) times.push_back(nlohmann::json::parse(m.payload).at("t_ns"));
  ASSERT_GE(times.size(), 5u);
  const double span_s = static_cast<double>(times.back() - times.front()) * 1e-9;
  EXPECT_LE(static_cast<double>(times.size() - 1), (span_s + 0.2 + 0.005) * 5.0)
      << times.size() << " postures in " << span_s << " s: posture_rate_hz = 5 of a 30 Hz stream";

  d->signal(SIGKILL);
  ASSERT_TRUE(sub.wait_for(test::scaled(10s), [&](const std::vector<MqttMessage>& ms) { return status_is(ms, "hall_B_1", "offline"); }))
      << "the last will, at once: the kernel closed the connection";
}

// Reads every line of a stream on its own thread (the daemon drops a
// client that stops reading).
class StreamRecorder {
 public:
  explicit StreamRecorder(LineClient client)
      : client_(std::move(client)), thread_([this] {
          while (!stop_)
            if (auto line = client_.read_line(200ms)) {
              std::lock_guard lock(mutex_);
              lines_.push_back(*line);
            }
        }) {}
  ~StreamRecorder() {
    stop_ = true;
    thread_.join();
  }
  // The summary and alert lines, by class.
  std::multiset<std::string> of_class(const std::string& kind) {
    std::lock_guard lock(mutex_);
    std::multiset<std::string> out;
    for (auto& l : lines_)
      if (l.find("\"class\":\"" + kind + "\"") != std::string::npos) out.insert(l);
    return out;
  }

 private:
  LineClient client_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::vector<std::string> lines_;
  std::thread thread_;
};

TEST_F(DaemonMqtt, ABrokerOutageOfThirtySecondsLosesNoSummaryOrAlert) {
  const std::uint16_t port = test::free_port();
  test::MosquittoBroker broker(dir_ / "broker", anonymous_listener(port), {port});
  ASSERT_TRUE(broker.start()) << broker.log();
  // A persistent session: the broker keeps what arrives for it while it
  // reconnects after the outage.
  test::MqttSubscriber sub({.port = port, .client_id = "outage-subscriber", .clean_session = false});
  ASSERT_TRUE(sub.wait_subscribed(test::scaled(5s)));
  auto d = daemon("outage", config("outage", "url = \"mqtt://127.0.0.1:" + std::to_string(port) +
                                                 "\"\nposture_rate_hz = 2\noutbox_path = \"" + (dir_ / "outbox.db").string() +
                                                 "\"\nreconnect_min_s = 0.5\nreconnect_max_s = 2\nkeepalive_s = 5\n"));
  auto client = connect("outage");
  ASSERT_TRUE(client) << d->log();
  StreamRecorder stream(std::move(*client));
  const std::string t = "spinewatch/outage/";
  ASSERT_TRUE(sub.wait_for(test::scaled(30s), [&](const std::vector<MqttMessage>& ms) {
    return count(ms, t + "summary") >= 2 && status_is(ms, "outage", "online");
  })) << d->log();

  broker.stop();
  std::this_thread::sleep_for(30s);
  ASSERT_TRUE(d->running()) << d->log();
  const auto during = stream.of_class("summary").size();
  ASSERT_TRUE(broker.start()) << broker.log();
  // Until everything made before the restart, and a little after, has come.
  ASSERT_TRUE(sub.wait_for(test::scaled(60s), [&](const std::vector<MqttMessage>& ms) {
    return count(ms, t + "summary") >= static_cast<int>(during) + 4;
  })) << d->log() << broker.log();
  d->signal(SIGTERM);
  ASSERT_EQ(d->wait_exit(test::scaled(10s)), 0) << d->log();
  EXPECT_TRUE(sub.wait_for(test::scaled(5s), [&](const std::vector<MqttMessage>& ms) { return status_is(ms, "outage", "offline"); }));
  std::this_thread::sleep_for(500ms);

  // Every summary and alert the stream carried also came over MQTT (at
  // least once: a message in flight when the link went may come twice).
  std::set<std::string> mqtt_summaries, mqtt_alerts;
  for (const auto& m : sub.messages()) {
    if (m.topic == t + "summary") mqtt_summaries.insert(m.payload);
    if (m.topic == t + "alert") mqtt_alerts.insert(m.payload);
  }
  const auto summaries = stream.of_class("summary");
  const auto alerts = stream.of_class("alert");
  EXPECT_GE(summaries.size(), 60u) << "30 s of 1 s summaries (interval and shift each)";
  EXPECT_GE(alerts.size(), 2u);
  for (const auto& s : summaries) EXPECT_TRUE(mqtt_summaries.count(s)) << "lost: " << s;
  for (const auto& a : alerts) EXPECT_TRUE(mqtt_alerts.count(a)) << "lost: " << a;
  // And the intervals over MQTT are back to back: no gap in end_ns.
  std::map<std::int64_t, std::int64_t> intervals;  // start_ns → end_ns
  for (const auto& s : mqtt_summaries) {
    auto j = nlohmann::json::parse(s);
    if (j.at("scope") == "interval") intervals[j.at("start_ns")] = j.at("end_ns");
  }
  ASSERT_GE(intervals.size(), 30u);
  for (auto it = std::next(intervals.begin()); it != intervals.end(); ++it)
    EXPECT_EQ(it->first, std::prev(it)->second) << "a gap between two intervals";
  const std::string log = d->log();
  EXPECT_NE(log.find("mqtt: connected to mqtt://127.0.0.1:" + std::to_string(port) + " again after"), std::string::npos) << log;
  // Logged once for the outage, however many attempts it took.
  std::size_t warnings = 0;
  for (auto pos = log.find("logged once per outage"); pos != std::string::npos; pos = log.find("logged once per outage", pos + 1))
    ++warnings;
  EXPECT_EQ(warnings, 1u) << log;
}

std::vector<std::string> outbox_payloads(const std::filesystem::path& path) {
  std::vector<std::string> out;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* s = nullptr;
    sqlite3_prepare_v2(db, "SELECT payload FROM outbox ORDER BY id", -1, &s, nullptr);
    while (s && sqlite3_step(s) == SQLITE_ROW) out.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(s, 0)));
    sqlite3_finalize(s);
  }
  sqlite3_close(db);
  return out;
}

TEST_F(DaemonMqtt, ARestartDeliversWhatWaitedInTheBoundedOutbox) {
  const std::uint16_t port = test::free_port();  // no broker yet
  const auto outbox = dir_ / "outbox.db";
  const auto cfg = config("restart", "url = \"mqtt://127.0.0.1:" + std::to_string(port) + "\"\nposture_rate_hz = 0\noutbox_path = \"" +
                                         outbox.string() + "\"\noutbox_max_messages = 4\nreconnect_min_s = 0.5\n");
  {
    auto d = daemon("restart", cfg);
    auto client = connect("restart");
    ASSERT_TRUE(client) << d->log();
    StreamRecorder stream(std::move(*client));
    for (auto deadline = std::chrono::steady_clock::now() + test::scaled(30s);
         stream.of_class("summary").size() < 8 && std::chrono::steady_clock::now() < deadline;)
      std::this_thread::sleep_for(50ms);
    ASSERT_GE(stream.of_class("summary").size(), 8u) << d->log();
    std::this_thread::sleep_for(300ms);  // handed to the outbox
    EXPECT_TRUE(wait_log(*d, "mqtt.outbox_max_messages): dropping the oldest (counted)", 2s)) << d->log();
    d->signal(SIGKILL);
    d->wait_exit(5s);
  }
  const auto pending = outbox_payloads(outbox);
  ASSERT_EQ(pending.size(), 4u) << "bounded at outbox_max_messages, kept across SIGKILL";
  test::MosquittoBroker broker(dir_ / "broker", anonymous_listener(port), {port});
  ASSERT_TRUE(broker.start()) << broker.log();
  test::MqttSubscriber sub({.port = port});
  ASSERT_TRUE(sub.wait_subscribed(test::scaled(5s)));
  auto d = daemon("restart", cfg);
  ASSERT_TRUE(sub.wait_for(test::scaled(30s), [&](const std::vector<MqttMessage>& ms) {
    std::set<std::string> got;
    for (auto& m : ms)
      if (m.topic == "spinewatch/restart/summary" || m.topic == "spinewatch/restart/alert") got.insert(m.payload);
    for (auto& p : pending)
      if (!got.count(p)) return false;
    return true;
  })) << d->log();
  EXPECT_NE(d->log().find("mqtt: 4 messages waiting in the outbox"), std::string::npos) << d->log();
  std::this_thread::sleep_for(1s);
  EXPECT_EQ(count(sub.messages(), "spinewatch/restart/posture"), 0) << "posture_rate_hz = 0: no postures";
}

// openssl, in the test directory: a CA, the broker's certificate for
// 127.0.0.1 signed by it, a client certificate, and an unrelated CA.
bool make_certificates(const std::filesystem::path& dir) {
  const std::string d = dir.string();
  const std::string script =
      "set -e; cd '" + d + "'\n"
      "openssl req -x509 -newkey rsa:2048 -nodes -keyout ca.key -out ca.crt -days 2 -subj /CN=test-ca 2>/dev/null\n"
      "openssl req -x509 -newkey rsa:2048 -nodes -keyout wrong.key -out wrong-ca.crt -days 2 -subj /CN=other-ca 2>/dev/null\n"
      "printf 'subjectAltName=IP:127.0.0.1,DNS:localhost\\n' > san.ext\n"
      "openssl req -newkey rsa:2048 -nodes -keyout server.key -out server.csr -subj /CN=127.0.0.1 2>/dev/null\n"
      "openssl x509 -req -in server.csr -CA ca.crt -CAkey ca.key -CAcreateserial -out server.crt -days 2 -extfile san.ext 2>/dev/null\n"
      "openssl req -newkey rsa:2048 -nodes -keyout client.key -out client.csr -subj /CN=station 2>/dev/null\n"
      "openssl x509 -req -in client.csr -CA ca.crt -CAkey ca.key -CAcreateserial -out client.crt -days 2 2>/dev/null\n"
      "chmod 644 *.key\n";
  test::write_file(dir / "make.sh", script);
  return test::run_command("/bin/sh '" + (dir / "make.sh").string() + "'").exit_code == 0;
}

TEST_F(DaemonMqtt, TlsWithATestCaWorksAndAWrongCaFailsAsDocumented) {
  if (::access("/usr/bin/openssl", X_OK) != 0) GTEST_SKIP() << "/usr/bin/openssl is not installed (Debian package openssl)";
  const auto certs = dir_ / "certs";
  std::filesystem::create_directories(certs);
  ASSERT_TRUE(make_certificates(certs));
  const std::uint16_t tls_port = test::free_port(), plain_port = test::free_port();
  const std::string c = certs.string();
  test::MosquittoBroker broker(dir_ / "broker",
                               "listener " + std::to_string(tls_port) + " 127.0.0.1\nallow_anonymous true\ncafile " + c +
                                   "/ca.crt\ncertfile " + c + "/server.crt\nkeyfile " + c +
                                   "/server.key\nrequire_certificate true\n" + anonymous_listener(plain_port),
                               {tls_port, plain_port});
  ASSERT_TRUE(broker.start()) << broker.log();
  test::MqttSubscriber sub({.port = plain_port});
  ASSERT_TRUE(sub.wait_subscribed(test::scaled(5s)));
  const std::string url = "url = \"mqtts://127.0.0.1:" + std::to_string(tls_port) + "\"\n";
  const std::string client_cert = "cert_file = \"" + c + "/client.crt\"\nkey_file = \"" + c + "/client.key\"\n";
  auto good = daemon("tls-good", config("tls-good", url + "ca_file = \"" + c + "/ca.crt\"\n" + client_cert +
                                                        "outbox_path = \"" + (dir_ / "good.db").string() + "\"\n"));
  auto wrong = daemon("tls-wrong", config("tls-wrong", url + "ca_file = \"" + c + "/wrong-ca.crt\"\n" + client_cert +
                                                           "outbox_path = \"" + (dir_ / "wrong.db").string() + "\"\n"));
  // Without the client certificate the broker (require_certificate) refuses.
  auto anonymous = daemon("tls-nocert", config("tls-nocert", url + "ca_file = \"" + c + "/ca.crt\"\noutbox_path = \"" +
                                                                 (dir_ / "nocert.db").string() + "\"\n"));
  ASSERT_TRUE(sub.wait_for(test::scaled(30s), [&](const std::vector<MqttMessage>& ms) {
    return status_is(ms, "tls-good", "online") && count(ms, "spinewatch/tls-good/summary") >= 1;
  })) << good->log() << broker.log();
  ASSERT_TRUE(wait_log(*wrong, "certificate verify failed", test::scaled(15s))) << wrong->log();
  EXPECT_TRUE(wait_log(*wrong, "logged once per outage", 1s)) << wrong->log();
  ASSERT_TRUE(wait_log(*anonymous, "logged once per outage", test::scaled(15s))) << anonymous->log();
  std::this_thread::sleep_for(1s);
  const auto ms = sub.messages();
  EXPECT_EQ(count(ms, "spinewatch/tls-wrong/status"), 0) << "never connected";
  EXPECT_EQ(count(ms, "spinewatch/tls-nocert/status"), 0) << "never connected";
  EXPECT_TRUE(wrong->running());
  EXPECT_TRUE(anonymous->running());
  // The stream runs on, saying the link is down.
  auto client = connect("tls-wrong");
  ASSERT_TRUE(client);
  bool seen = false;
  for (int i = 0; i < 200 && !seen; ++i) {
    auto line = client->read_line(test::scaled(3s));
    ASSERT_TRUE(line) << wrong->log();
    auto j = nlohmann::json::parse(*line);
    if (j.contains("stats")) {
      EXPECT_EQ(j.at("stats").at("mqtt_connected"), 0);
      seen = true;
    }
  }
  EXPECT_TRUE(seen);
}

TEST_F(DaemonMqtt, AWrongPasswordIsRefusedCountedLoggedAndTheDaemonRunsOn) {
  const std::uint16_t port = test::free_port();
  const auto passwords = dir_ / "broker-passwords";
  ASSERT_EQ(test::run_command("/usr/bin/mosquitto_passwd -c -b '" + passwords.string() + "' station right-pw").exit_code, 0);
  test::MosquittoBroker broker(dir_ / "broker",
                               "listener " + std::to_string(port) + " 127.0.0.1\nallow_anonymous false\npassword_file " +
                                   passwords.string() + "\n",
                               {port});
  ASSERT_TRUE(broker.start()) << broker.log();
  test::MqttSubscriber sub({.port = port, .username = "station", .password = "right-pw"});
  ASSERT_TRUE(sub.wait_subscribed(test::scaled(5s))) << broker.log();
  auto pw_file = [&](const std::string& name, const std::string& pw) {
    const auto p = dir_ / name;
    test::write_file(p, pw + "\n");
    ::chmod(p.c_str(), 0600);
    return p.string();
  };
  const std::uint16_t http = test::free_port();
  auto bad = daemon("pw-wrong",
                    config("pw-wrong", "url = \"mqtt://127.0.0.1:" + std::to_string(port) + "\"\nusername = \"station\"\npassword_file = \"" +
                                           pw_file("wrong.pw", "wrong-pw") + "\"\noutbox_path = \"" +
                                           (dir_ / "wrong.db").string() + "\"\nreconnect_min_s = 0.2\nreconnect_max_s = 0.4\n"),
                    {"--http", "127.0.0.1:" + std::to_string(http)});
  auto good = daemon("pw-right", config("pw-right", "url = \"mqtt://127.0.0.1:" + std::to_string(port) +
                                                        "\"\nusername = \"station\"\npassword_file = \"" +
                                                        pw_file("right.pw", "right-pw") + "\"\noutbox_path = \"" +
                                                        (dir_ / "right.db").string() + "\"\n"));
  ASSERT_TRUE(sub.wait_for(test::scaled(30s), [&](const std::vector<MqttMessage>& ms) { return status_is(ms, "pw-right", "online"); }))
      << good->log() << broker.log();
  ASSERT_TRUE(wait_log(*bad, "the broker refused the connection", test::scaled(15s))) << bad->log();
  EXPECT_NE(bad->log().find("not authorised"), std::string::npos) << bad->log();
  // Counted, and retried with back-off; the daemon serves on.
  std::string metrics;
  ASSERT_TRUE(test::eventually(
      [&] {
        metrics = test::http_get(http, "/metrics").body;
        const std::string name = "spinewatch_mqtt_connect_failures_total{reason=\"auth\"} ";
        const auto at = metrics.find(name);
        return at != std::string::npos && std::atoi(metrics.c_str() + at + name.size()) >= 3;
      },
      test::scaled(15s)))
      << metrics << bad->log();
  EXPECT_NE(metrics.find("spinewatch_mqtt_connected 0"), std::string::npos) << metrics;
  EXPECT_TRUE(bad->running());
  auto client = connect("pw-wrong");
  ASSERT_TRUE(client);
  EXPECT_TRUE(client->read_line(test::scaled(5s))) << "the stream flows";
  EXPECT_EQ(count(sub.messages(), "spinewatch/pw-wrong/status"), 0);
}

}  // namespace
}  // namespace spinewatch
