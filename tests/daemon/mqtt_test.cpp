// [mqtt] (docs/fleet.md): the keys, the URL, the topic-safe station name,
// the back-off, the password file, the persistent outbox, the metrics and
// stream stats, and the publisher itself against a real mosquitto broker
// (skipped, with the reason, where /usr/sbin/mosquitto is not installed).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>

#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include "http/daemon_metrics.hpp"
#include "mqtt/mqtt_outbox.hpp"
#include "mqtt/mqtt_publisher.hpp"
#include "mqtt_broker.hpp"
#include "publish/stream_lines.hpp"
#include "spinewatch/daemon/config.hpp"
#include "support/mqtt_url.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

TEST(MqttConfig, KeysAreReadWithTheirDefaults) {
  const Config::Mqtt d;
  EXPECT_EQ(d.url, "") << "off by default";
  EXPECT_EQ(d.qos, 0);
  EXPECT_EQ(d.posture_rate_hz, 1.0);
  auto c = parse_config("[mqtt]\nurl = \"mqtts://broker.site:8883\"\nca_file = \"/etc/ca.pem\"\ncert_file = \"c.pem\"\n"
                        "key_file = \"k.pem\"\nusername = \"desk-3\"\npassword_file = \"/run/pw\"\nposture_rate_hz = 2.5\n"
                        "qos = 1\noutbox_path = \"/var/lib/x/o.db\"\noutbox_max_messages = 50\nkeepalive_s = 17\n"
                        "reconnect_min_s = 0.5\nreconnect_max_s = 10\n",
                        "m.toml");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c->mqtt.url, "mqtts://broker.site:8883");
  EXPECT_EQ(c->mqtt.ca_file, "/etc/ca.pem");
  EXPECT_EQ(c->mqtt.cert_file, "c.pem");
  EXPECT_EQ(c->mqtt.key_file, "k.pem");
  EXPECT_EQ(c->mqtt.username, "desk-3");
  EXPECT_EQ(c->mqtt.password_file, "/run/pw");
  EXPECT_EQ(c->mqtt.posture_rate_hz, 2.5);
  EXPECT_EQ(c->mqtt.qos, 1);
  EXPECT_EQ(c->mqtt.outbox_path, "/var/lib/x/o.db");
  EXPECT_EQ(c->mqtt.outbox_max_messages, 50);
  EXPECT_EQ(c->mqtt.keepalive_s, 17);
  EXPECT_EQ(c->mqtt.reconnect_min_s, 0.5);
  EXPECT_EQ(c->mqtt.reconnect_max_s, 10.0);
}

TEST(MqttConfig, ABadValueNamesKeyAndLine) {
  auto error = [](const std::string& text) { return parse_config(text, "m.toml").error().message; };
  EXPECT_EQ(error("[mqtt]\nurl = \"http://broker:1883\"\n"),
            "m.toml:2: mqtt.url: \"http://broker:1883\": expected mqtt://HOST:PORT or mqtts://HOST:PORT (or \"\" for off)");
  EXPECT_EQ(error("\n[mqtt]\nurl = \"mqtt://broker\"\n"), "m.toml:3: mqtt.url: \"mqtt://broker\": no port (expected mqtt://HOST:PORT)");
  EXPECT_EQ(error("[mqtt]\nqos = 2\n"), "m.toml:2: mqtt.qos: 2 is out of range [0, 1]");
  EXPECT_EQ(error("[mqtt]\nposture_rate_hz = -1\n"), "m.toml:2: mqtt.posture_rate_hz: -1 is out of range [0, 120]");
  EXPECT_EQ(error("[mqtt]\nkeepalive_s = 1\n"), "m.toml:2: mqtt.keepalive_s: 1 is out of range [5, 3600]");
  EXPECT_EQ(error("[mqtt]\noutbox_max_messages = 0\n"), "m.toml:2: mqtt.outbox_max_messages: 0 is out of range [1, 10000000]");
  EXPECT_EQ(error("[mqtt]\nusername = 3\n"), "m.toml:2: mqtt.username: expected a string, got integer");
  EXPECT_EQ(error("[mqtt]\nport = 1883\n"), "m.toml:2: mqtt.port: unknown key");
  // Keys taken together.
  EXPECT_EQ(error("[mqtt]\nurl = \"mqtt://b:1883\"\nca_file = \"ca.pem\"\n"),
            "m.toml:3: mqtt.ca_file: set, but mqtt.url is not mqtts://: a plain connection has no TLS");
  EXPECT_EQ(error("[mqtt]\nurl = \"mqtts://b:8883\"\ncert_file = \"c.pem\"\n"),
            "m.toml:3: mqtt.cert_file: the client certificate and its key go together: give both");
  EXPECT_EQ(error("[mqtt]\nurl = \"mqtt://b:1883\"\npassword_file = \"pw\"\n"),
            "m.toml:3: mqtt.password_file: set without mqtt.username");
  EXPECT_EQ(error("[mqtt]\nreconnect_min_s = 5\nreconnect_max_s = 2\n"),
            "m.toml:2: mqtt.reconnect_min_s: 5 is above mqtt.reconnect_max_s (2)");
}

TEST(MqttUrlTest, TakesBothSchemesAndRefusesTheRest) {
  EXPECT_EQ(parse_mqtt_url("mqtt://127.0.0.1:1883").value(), (MqttUrl{false, "127.0.0.1", 1883}));
  EXPECT_EQ(parse_mqtt_url("mqtts://broker.example.org:8883").value(), (MqttUrl{true, "broker.example.org", 8883}));
  EXPECT_EQ(parse_mqtt_url("mqtt://[::1]:1883").value(), (MqttUrl{false, "::1", 1883}));
  for (const char* bad : {"", "broker:1883", "tcp://b:1883", "mqtt://b", "mqtt://:1883", "mqtt://b:0", "mqtt://b:65536",
                          "mqtt://b:18x3", "mqtt://b:1883/topic", "mqtt://user:pw@b:1883", "mqtt://::1:1883", "mqtt://[::1]"})
    EXPECT_FALSE(parse_mqtt_url(bad)) << bad;
}

TEST(MqttTopics, TheStationBecomesOneSafeTopicLevel) {
  EXPECT_EQ(topic_safe_station("desk-3"), "desk-3");
  EXPECT_EQ(topic_safe_station("hall/B+#1"), "hall_B__1");
  EXPECT_EQ(topic_safe_station(std::string("a\nb\0c", 5)), "a_b_c");
  EXPECT_EQ(topic_safe_station("Bänk 3"), "Bänk 3");
  EXPECT_EQ(topic_safe_station(""), "_");
}

TEST(MqttBackoff, DoublesFromMinUpToMax) {
  EXPECT_EQ(mqtt_reconnect_delay(1, 1.0, 60.0), 1000ms);
  EXPECT_EQ(mqtt_reconnect_delay(2, 1.0, 60.0), 2000ms);
  EXPECT_EQ(mqtt_reconnect_delay(4, 1.0, 60.0), 8000ms);
  EXPECT_EQ(mqtt_reconnect_delay(7, 1.0, 60.0), 60000ms);
  EXPECT_EQ(mqtt_reconnect_delay(1000, 1.0, 60.0), 60000ms);
  EXPECT_EQ(mqtt_reconnect_delay(1, 0.25, 0.5), 250ms);
  EXPECT_EQ(mqtt_reconnect_delay(3, 0.25, 0.5), 500ms);
}

Config mqtt_config(const std::string& extra) {
  auto c = parse_config("[mqtt]\nurl = \"mqtt://127.0.0.1:1883\"\n" + extra, "m.toml");
  EXPECT_TRUE(c) << c.error().message;
  return c ? *c : Config{};
}

TEST(MqttOptionsTest, ThePasswordFileIsReadAndMustBePrivate) {
  test::TempDir dir;
  const auto pw = dir / "pw";
  test::write_file(pw, "s3cret\n");
  ::chmod(pw.c_str(), 0644);
  const Config c = mqtt_config("username = \"u\"\npassword_file = \"" + pw.string() + "\"\n");
  auto refused = mqtt_options(c);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().message,
            "mqtt.password_file: " + pw.string() + ": mode 0644 lets group or others read it; `chmod 600 " + pw.string() +
                "` (or give it with systemd's LoadCredential=, docs/fleet.md)");
  ::chmod(pw.c_str(), 0600);
  auto o = mqtt_options(c);
  ASSERT_TRUE(o) << o.error().message;
  ASSERT_TRUE(*o);
  EXPECT_EQ((*o)->password, "s3cret");
  EXPECT_EQ((*o)->username, "u");
  test::write_file(pw, "\n");
  EXPECT_EQ(mqtt_options(c).error().message, "mqtt.password_file: " + pw.string() + ": empty");
  EXPECT_FALSE(mqtt_options(mqtt_config("username = \"u\"\npassword_file = \"/nonexistent/pw\"\n")));
}

TEST(MqttOptionsTest, OffWithoutAUrlAndTheOutboxDefaultsToTheStateDirectory) {
  auto off = mqtt_options(Config{});
  ASSERT_TRUE(off);
  EXPECT_FALSE(*off);
  ::setenv("STATE_DIRECTORY", "/var/lib/spinewatch-x:/other", 1);
  auto o = mqtt_options(mqtt_config(""));
  ::unsetenv("STATE_DIRECTORY");
  ASSERT_TRUE(o && *o);
  EXPECT_EQ((*o)->outbox_path, "/var/lib/spinewatch-x/mqtt-outbox.db");
  // Off systemd: /var/lib/spinewatch where this process may write, else the user's state directory.
  test::TempDir home;
  ::setenv("XDG_STATE_HOME", home.path().c_str(), 1);
  auto by_hand = mqtt_options(mqtt_config(""));
  ::unsetenv("XDG_STATE_HOME");
  ASSERT_TRUE(by_hand) << by_hand.error().message;
  const std::filesystem::path system_dir = "/var/lib/spinewatch";
  const bool system = ::access(system_dir.c_str(), W_OK) == 0;
  EXPECT_EQ((*by_hand)->outbox_path, (system ? system_dir : home.path() / "spinewatch") / "mqtt-outbox.db");
  EXPECT_EQ((*mqtt_options(mqtt_config("outbox_path = \"/tmp/o.db\"\n")))->outbox_path, "/tmp/o.db");
  auto tls = parse_config("[mqtt]\nurl = \"mqtts://127.0.0.1:8883\"\nca_file = \"/nonexistent/ca.pem\"\n", "m.toml");
  ASSERT_TRUE(tls);
  EXPECT_EQ(mqtt_options(*tls).error().message, "mqtt.ca_file: /nonexistent/ca.pem: cannot be read");
}

TEST(MqttOutboxTest, KeepsMessagesAcrossReopeningUntilRemovedAndDropsTheOldestWhenFull) {
  test::TempDir dir;
  const auto path = dir / "outbox.db";
  {
    auto box = MqttOutbox::open(path, 3);
    ASSERT_TRUE(box) << box.error().message;
    EXPECT_EQ((*box)->append(MqttTopic::Summary, "s1").value(), 0u);
    EXPECT_EQ((*box)->append(MqttTopic::Alert, "a1").value(), 0u);
    EXPECT_EQ((*box)->size(), 2u);
  }
  auto box = MqttOutbox::open(path, 3);
  ASSERT_TRUE(box) << box.error().message;
  EXPECT_EQ((*box)->size(), 2u) << "kept across a reopen (a restart)";
  auto all = (*box)->after(0, 10).value();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].topic, MqttTopic::Summary);
  EXPECT_EQ(all[1].topic, MqttTopic::Alert);
  EXPECT_EQ(all[0].payload, "s1");
  EXPECT_EQ(all[1].payload, "a1");
  EXPECT_LT(all[0].id, all[1].id);
  EXPECT_EQ((*box)->after(all[0].id, 10).value().size(), 1u);
  EXPECT_EQ((*box)->append(MqttTopic::Summary, "s2").value(), 0u);
  EXPECT_EQ((*box)->append(MqttTopic::Summary, "s3").value(), 1u) << "full at 3: the oldest goes";
  all = (*box)->after(0, 10).value();
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].payload, "a1");
  EXPECT_EQ(all[2].payload, "s3");
  ASSERT_TRUE((*box)->remove(all[1].id));
  ASSERT_TRUE((*box)->remove(all[1].id)) << "removing twice is no error";
  EXPECT_EQ((*box)->size(), 2u);
  EXPECT_EQ((*box)->after(0, 1).value().size(), 1u) << "limit";
}

// The file holds each topic by its name (the broker's last level), read
// back as the enum; a name spinewatchd does not publish is refused at open,
// naming the file and the message.
TEST(MqttOutboxTest, StoresTopicsByNameAndRefusesAFileWithAnotherTopic) {
  test::TempDir dir;
  const auto path = dir / "outbox.db";
  {
    auto box = MqttOutbox::open(path, 10);
    ASSERT_TRUE(box) << box.error().message;
    ASSERT_TRUE((*box)->append(MqttTopic::Alert, "a1"));
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  std::string names;
  sqlite3_exec(
      db, "SELECT topic FROM outbox",
      [](void* out, int, char** values, char**) {
        *static_cast<std::string*>(out) += values[0];
        return 0;
      },
      &names, nullptr);
  EXPECT_EQ(names, "alert") << "the name MQTT sees, as files written before the enum hold it";
  ASSERT_EQ(sqlite3_exec(db, "INSERT INTO outbox (topic, payload) VALUES ('telemetry', 't1')", nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  auto box = MqttOutbox::open(path, 10);
  ASSERT_FALSE(box);
  EXPECT_EQ(box.error().message, "mqtt outbox " + path.string() +
                                     ": message 2 has the topic \"telemetry\", which spinewatchd does not publish "
                                     "(summary, alert): a file of another program? Move it away, or give "
                                     "mqtt.outbox_path another file");
}

TEST(MqttTopicNames, EachTopicHasOneNameThatParsesBack) {
  for (MqttTopic t : {MqttTopic::Status, MqttTopic::Posture, MqttTopic::Summary, MqttTopic::Alert})
    EXPECT_EQ(parse_topic_leaf(topic_leaf(t)), t) << topic_leaf(t);
  EXPECT_EQ(topic_leaf(MqttTopic::Summary), "summary");
  EXPECT_FALSE(parse_topic_leaf("Summary")) << "names are exact";
  EXPECT_FALSE(parse_topic_leaf(""));
}

TEST(MqttMetrics, FamiliesOnlyWhileMqttIsConfigured) {
  DaemonMetrics m;
  EXPECT_EQ(metrics_text(m).find("spinewatch_mqtt"), std::string::npos);
  m.mqtt = MqttStats{.connected = true, .outbox_messages = 4, .dropped_disconnected = 7, .reconnects = 2, .failed_auth = 3,
                     .published_summary = 5};
  const std::string text = metrics_text(m);
  for (const char* sample : {"spinewatch_mqtt_connected 1\n", "spinewatch_mqtt_outbox_messages 4\n",
                             "spinewatch_mqtt_dropped_total{reason=\"disconnected\"} 7\n",
                             "spinewatch_mqtt_reconnects_total 2\n", "spinewatch_mqtt_published_total{topic=\"summary\"} 5\n",
                             "spinewatch_mqtt_connect_failures_total{reason=\"auth\"} 3\n"})
    EXPECT_NE(text.find(sample), std::string::npos) << sample << text;
}

TEST(MqttStreamStats, ThePostureLinesStatsCarryTheLinkOnlyWithMqtt) {
  StreamStats s;
  auto line = nlohmann::json::parse(encode_posture_line(test::sample_tracking_posture(), s));
  EXPECT_FALSE(line.at("stats").contains("mqtt_outbox"));
  s.mqtt = true;
  s.mqtt_connected = 1;
  s.mqtt_outbox = 3;
  s.mqtt_dropped = 9;
  s.mqtt_reconnects = 2;
  line = nlohmann::json::parse(encode_posture_line(test::sample_tracking_posture(), s));
  EXPECT_EQ(line.at("stats").at("mqtt_connected"), 1);
  EXPECT_EQ(line.at("stats").at("mqtt_outbox"), 3);
  EXPECT_EQ(line.at("stats").at("mqtt_dropped"), 9);
  EXPECT_EQ(line.at("stats").at("mqtt_reconnects"), 2);
}

MqttOptions options_for(std::uint16_t port, const std::filesystem::path& outbox) {
  MqttOptions o;
  o.url = {false, "127.0.0.1", port};
  o.station = "hall/B+1";
  o.outbox_path = outbox;
  o.reconnect_min_s = 0.2;
  o.reconnect_max_s = 0.2;
  return o;
}

// No broker: attempts fail at the back-off's pace, summaries wait in the
// outbox, postures due are dropped and counted, never queued.
TEST(MqttPublisherTest, WithoutABrokerSummariesWaitAndPosturesAreCountedDropped) {
  test::TempDir dir;
  const std::uint16_t port = test::free_port();
  auto fast = options_for(port, dir / "fast.db");
  fast.posture_rate_hz = 5;
  auto slow = options_for(port, dir / "slow.db");
  slow.reconnect_min_s = 1.0;
  slow.reconnect_max_s = 1.0;
  auto a = MqttPublisher::start(fast);
  auto b = MqttPublisher::start(slow);
  ASSERT_TRUE(a && b);
  (*a)->publish_summary("{\"class\":\"summary\"}");
  (*a)->publish_alert("{\"class\":\"alert\"}");
  // Two seconds of postures at 30 Hz: 10 due at 5 Hz.
  for (int i = 0; i < 60; ++i) (*a)->offer_posture(std::int64_t(i) * 33'333'333, "{}");
  std::this_thread::sleep_for(1500ms);
  const MqttStats sa = (*a)->stats(), sb = (*b)->stats();
  EXPECT_FALSE(sa.connected);
  EXPECT_EQ(sa.outbox_messages, 2u);
  EXPECT_EQ(sa.dropped_disconnected, 10u);
  EXPECT_EQ(sa.dropped_queue_full, 0u);
  // Attempts every 0.2 s against every 1 s (the first at once).
  EXPECT_GE(sa.failed_network, 5u);
  EXPECT_LE(sb.failed_network, 3u);
  EXPECT_GE(sb.failed_network, 1u);
  EXPECT_EQ(sa.reconnects, 0u);
  EXPECT_EQ((*a)->topic(MqttTopic::Status), "spinewatch/hall_B_1/status");
  EXPECT_EQ((*a)->prefix(), "spinewatch/hall_B_1/");
}

// A real broker: status online (retained), summaries and alerts at QoS 1
// leave the outbox once acknowledged, postures decimated by their time at
// the configured QoS, the keep-alive as configured.
TEST(MqttPublisherTest, PublishesTheDocumentedTopicsToARealBroker) {
  if (!test::mosquitto_available()) GTEST_SKIP() << test::kMosquitto << " is not installed (Debian package mosquitto)";
  test::TempDir dir;
  const std::uint16_t port = test::free_port();
  test::MosquittoBroker broker(dir / "broker", "listener " + std::to_string(port) + " 127.0.0.1\nallow_anonymous true\n", {port});
  ASSERT_TRUE(broker.start()) << broker.log();
  test::MqttSubscriber sub({.port = port});
  ASSERT_TRUE(sub.wait_subscribed(test::scaled(5s)));
  for (int qos : {0, 1}) {
    auto o = options_for(port, dir / ("outbox" + std::to_string(qos) + ".db"));
    o.station = "desk " + std::to_string(qos);
    o.qos = qos;
    o.posture_rate_hz = 5;
    o.keepalive_s = 17 + qos;
    auto p = MqttPublisher::start(o);
    ASSERT_TRUE(p) << p.error().message;
    const std::string prefix = "spinewatch/desk " + std::to_string(qos) + "/";
    for (auto deadline = std::chrono::steady_clock::now() + test::scaled(5s);
         !(*p)->stats().connected && std::chrono::steady_clock::now() < deadline;)
      std::this_thread::sleep_for(10ms);
    ASSERT_TRUE((*p)->stats().connected) << broker.log();
    (*p)->publish_summary("{\"s\":1}");
    (*p)->publish_alert("{\"a\":1}");
    for (int i = 0; i < 60; ++i) {
      (*p)->offer_posture(std::int64_t(i) * 33'333'333, "{\"i\":" + std::to_string(i) + "}");
      std::this_thread::sleep_for(2ms);
    }
    ASSERT_TRUE(sub.wait_for(test::scaled(5s), [&](const std::vector<test::MqttMessage>& ms) {
      int postures = 0, summaries = 0, alerts = 0;
      for (auto& m : ms) {
        postures += m.topic == prefix + "posture";
        summaries += m.topic == prefix + "summary";
        alerts += m.topic == prefix + "alert";
      }
      return postures == 10 && summaries == 1 && alerts == 1;
    })) << broker.log();
    for (auto& m : sub.on(prefix + "posture")) EXPECT_EQ(m.qos, qos) << "posture QoS as configured";
    EXPECT_EQ(sub.on(prefix + "posture").front().payload, "{\"i\":0}");
    EXPECT_EQ(sub.on(prefix + "posture")[1].payload, "{\"i\":6}") << "5 Hz of a 30 Hz stream: every sixth";
    EXPECT_EQ(sub.on(prefix + "summary").at(0).qos, 1);
    EXPECT_EQ(sub.on(prefix + "summary").at(0).payload, "{\"s\":1}");
    EXPECT_EQ(sub.on(prefix + "alert").at(0).qos, 1);
    EXPECT_EQ(sub.on(prefix + "status").at(0).payload, "online");
    for (auto deadline = std::chrono::steady_clock::now() + test::scaled(2s);
         ((*p)->stats().outbox_messages > 0 || (*p)->stats().published_posture < 10) &&
         std::chrono::steady_clock::now() < deadline;)
      std::this_thread::sleep_for(10ms);
    const MqttStats s = (*p)->stats();
    EXPECT_EQ(s.outbox_messages, 0u) << "acknowledged: gone from the outbox";
    EXPECT_EQ(s.published_summary, 1u);
    EXPECT_EQ(s.published_alert, 1u);
    EXPECT_EQ(s.published_posture, 10u);
    EXPECT_EQ(s.published_status, 1u);
    (*p)->stop();
    ASSERT_TRUE(sub.wait_for(test::scaled(3s), [&](const std::vector<test::MqttMessage>& ms) {
      auto last = test::last_on(ms, prefix + "status");
      return last && last->payload == "offline";
    })) << "a clean stop says offline";
    EXPECT_NE(broker.log().find("k" + std::to_string(17 + qos) + ")"), std::string::npos) << "keepalive_s reaches the broker";
  }
  // Retained: a subscriber that comes later still learns the status.
  test::MqttSubscriber late({.port = port, .client_id = "late"});
  ASSERT_TRUE(late.wait_for(test::scaled(5s), [](const std::vector<test::MqttMessage>& ms) {
    auto last = test::last_on(ms, "spinewatch/desk 1/status");
    return last && last->payload == "offline" && last->retain;
  }));
}

}  // namespace
}  // namespace spinewatch
