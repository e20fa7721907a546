// The daemon's network loop (daemon/src/net/network_loop.hpp): both
// servers, the posture stream's publisher and the HTTP live view, on one
// loop that neither owns; the stop order the daemon keeps (servers, then
// the loop) and the one after a failed start (the loop first).
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <chrono>
#include <filesystem>

#include <spdlog/spdlog.h>

#include "http/http_server.hpp"
#include "http/live_view.hpp"
#include "http_client.hpp"
#include "net/network_loop.hpp"
#include "publish/publisher.hpp"
#include "test_client.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;
using test::LineClient;

const std::string kLoopHello = R"({"class":"hello","v":1,"daemon_version":"test","station":"loop"})";

class NetworkLoopTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spdlog::set_level(spdlog::level::warn);
    PublisherOptions p;
    p.tcp = TcpEndpoint{"127.0.0.1", 0};
    p.unix_socket = socket_path;
    auto publisher = Publisher::start(loop->io(), p, kLoopHello);
    ASSERT_TRUE(publisher) << publisher.error().message;
    pub = std::move(publisher).value();
    live = std::make_unique<LiveView>(CameraRig::default_rig(), LiveViewOptions{}, [](auto) {});
    StationInfo station;
    station.station = "loop";
    auto server = HttpServer::start(loop->io(), HttpOptions{.endpoint = {"127.0.0.1", 0}}, HttpHandlers{}, station, *live);
    ASSERT_TRUE(server) << server.error().message;
    http = std::move(server).value();
  }
  void TearDown() override { spdlog::set_level(spdlog::level::info); }

  test::TempDir dir;
  const std::filesystem::path socket_path = dir.path() / "p.sock";
  // Declared before the servers: destroyed after them, as in the daemon.
  std::unique_ptr<net::NetworkLoop> loop = std::make_unique<net::NetworkLoop>("test loop");
  std::unique_ptr<Publisher> pub;
  std::unique_ptr<LiveView> live;
  std::unique_ptr<HttpServer> http;
};

TEST_F(NetworkLoopTest, BothServersServeOnTheOneLoopAndCloseCleanlyBeforeItStops) {
  EXPECT_EQ(&pub->io_context(), &loop->io()) << "the publisher serves on the loop it was handed";
  auto client = LineClient::tcp(pub->tcp_port());
  EXPECT_EQ(client.read_line(), kLoopHello);
  const auto metrics = test::http_get(http->port(), "/metrics");
  EXPECT_EQ(metrics.status, 200);
  EXPECT_NE(metrics.body.find("spinewatch_http_requests_total"), std::string::npos) << metrics.body;
  pub->publish(R"({"class":"posture","seq":1})");
  EXPECT_EQ(client.read_line(), R"({"class":"posture","seq":1})");

  // The daemon's order: each server closes its clients on the running loop, then the loop stops.
  http->stop();
  pub->stop();
  EXPECT_TRUE(client.wait_closed(2s)) << "the publisher's client was closed";
  EXPECT_FALSE(std::filesystem::exists(socket_path)) << "the socket file is removed at stop";
  loop->stop();
}

// After a failed start the daemon stops its loop first: the servers then
// close at once, without waiting on a loop that no thread runs.
TEST_F(NetworkLoopTest, ServersStopAtOnceWhenTheLoopHasStopped) {
  auto client = LineClient::tcp(pub->tcp_port());
  EXPECT_EQ(client.read_line(), kLoopHello);
  loop->stop();
  const auto t0 = std::chrono::steady_clock::now();
  http->stop();
  pub->stop();
  const auto took = std::chrono::steady_clock::now() - t0;
  EXPECT_LT(took, 500ms) << "a stop waited for a loop that no longer runs";
  EXPECT_FALSE(std::filesystem::exists(socket_path)) << "the socket file is removed at stop";
  http.reset();
  pub.reset();
  loop.reset();  // what the loop still held (the session's pending read) goes with it
  EXPECT_TRUE(client.wait_closed(2s)) << "the client's connection ends with the loop";
}

}  // namespace
}  // namespace spinewatch
