// The HTTP live view's pieces: routes, the latency histogram, the
// Prometheus page (parsed by python3-prometheus-client), the /state
// document (validated against docs/state.schema.json), view coverage, and
// the server itself on a real socket: malformed and oversized requests,
// wrong methods, the connection limit, a request that never finishes, and
// the background re-learn endpoint.
#include <gtest/gtest.h>

#include <thread>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include "http/daemon_metrics.hpp"
#include "http/http_routes.hpp"
#include "http/http_server.hpp"
#include "http/state_json.hpp"
#include "http_client.hpp"
#include "spinewatch/estimator/silhouette/view_coverage.hpp"
#include "spinewatch/frames/clock.hpp"
#include "test_client.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

TEST(HttpRoutes, PathsAndUstreamerActions) {
  EXPECT_EQ(route_of("/"), HttpRoute::Page);
  EXPECT_EQ(route_of("/?view=poll"), HttpRoute::Page);
  EXPECT_EQ(route_of("/?action=stream"), HttpRoute::Stream);
  EXPECT_EQ(route_of("/?x=1&action=snapshot"), HttpRoute::Snapshot);
  EXPECT_EQ(route_of("/?action=bogus"), HttpRoute::NotFound);
  EXPECT_EQ(route_of("/stream"), HttpRoute::Stream);
  EXPECT_EQ(route_of("/snapshot?seq=4"), HttpRoute::Snapshot);
  EXPECT_EQ(route_of("/state"), HttpRoute::State);
  EXPECT_EQ(route_of("/metrics"), HttpRoute::Metrics);
  EXPECT_EQ(route_of("/background/relearn"), HttpRoute::RelearnBackground);
  EXPECT_EQ(route_of("/streamx"), HttpRoute::NotFound);
  EXPECT_EQ(route_of("/../etc/passwd"), HttpRoute::NotFound);
  EXPECT_EQ(method_of(HttpRoute::RelearnBackground), "POST");
  EXPECT_EQ(method_of(HttpRoute::Stream), "GET");
}

TEST(LatencyHistogram, BucketsByUpperBoundInclusive) {
  LatencyHistogram h;
  h.observe_us(100);      // ≤ 0.25 ms
  h.observe_us(250);      // = 0.25 ms: the same bucket (le is inclusive)
  h.observe_us(251);      // ≤ 0.5 ms
  h.observe_us(40'000);   // ≤ 50 ms
  h.observe_us(2'000'000);  // +Inf
  const auto c = h.counts();
  EXPECT_EQ(c.count, 5u);
  EXPECT_NEAR(c.sum_s, 2.040601, 1e-9);
  EXPECT_EQ(c.buckets[0], 2u);
  EXPECT_EQ(c.buckets[1], 1u);
  EXPECT_EQ(c.buckets[7], 1u);
  EXPECT_EQ(c.buckets.back(), 1u);
}

DaemonMetrics sample_metrics() {
  DaemonMetrics m;
  m.pipeline.pairs = 1000;
  m.pipeline.pairs_processed = 990;
  m.pipeline.pairs_dropped = 10;
  m.pipeline.pair_queue = 2;
  m.pipeline.pair_queue_capacity = 4;
  m.pipeline.source.frames = 2010;
  m.pipeline.source.frames_lost = 10;
  m.pipeline.source.camera[0] = {.frames = 1004, .restarts = 1, .losses = 2};
  m.pipeline.source.camera[1] = {.frames = 1006, .restarts = 0};
  m.publisher.clients = 3;
  m.publisher.clients_dropped = 2;
  m.publisher.clients_rejected = 1;
  m.publisher.lines = 990;
  m.publisher.inbox_capacity = 1024;
  m.postures.by_state = {20, 950, 20};
  m.postures.tracking_lost = 4;
  m.background = {.updates = 900, .relearns = 1, .bootstraps = 2};
  LatencyHistogram h;
  for (int us : {300, 400, 900, 1500, 60'000}) h.observe_us(us);
  m.latency = h.counts();
  m.http.stream_viewers = 5;
  m.http.timed_out = 7;
  m.live.mailbox_capacity = 2;
  m.pairs_per_s = 29.97;
  m.uptime_s = 33.4;
  return m;
}

// name{labels} → value, as python3-prometheus-client parsed the page.
std::map<std::string, double> parse_with_prometheus_client(const std::string& page, std::string& families) {
  test::TempDir dir;
  test::write_file(dir / "metrics.txt", page);
  const auto r = test::run_command("/usr/bin/python3 '" + test::source_path("tests/support/parse_metrics.py").string() +
                                   "' '" + (dir / "metrics.txt").string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::map<std::string, double> samples;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("# family ", 0) == 0) {
      families += line.substr(9) + "\n";
      continue;
    }
    const auto space = line.rfind(' ');
    if (space != std::string::npos) samples[line.substr(0, space)] = std::stod(line.substr(space + 1));
  }
  return samples;
}

TEST(MetricsText, ParsesWithPrometheusClientAndCarriesTheCounters) {
  std::string families;
  const auto s = parse_with_prometheus_client(metrics_text(sample_metrics()), families);
  ASSERT_FALSE(s.empty());
  EXPECT_EQ(s.at("spinewatch_pairs_total{}"), 1000);
  EXPECT_EQ(s.at("spinewatch_pairs_processed_total{}"), 990);
  EXPECT_EQ(s.at("spinewatch_pairs_dropped_total{reason=\"estimator_behind\"}"), 10);
  EXPECT_EQ(s.at("spinewatch_frames_total{camera=\"frontal\"}"), 1004);
  EXPECT_EQ(s.at("spinewatch_frames_total{camera=\"lateral\"}"), 1006);
  EXPECT_EQ(s.at("spinewatch_camera_restarts_total{camera=\"frontal\"}"), 1);
  EXPECT_EQ(s.at("spinewatch_camera_losses_total{camera=\"frontal\"}"), 2);
  EXPECT_EQ(s.at("spinewatch_camera_losses_total{camera=\"lateral\"}"), 0);
  EXPECT_EQ(s.at("spinewatch_postures_total{state=\"tracking\"}"), 950);
  EXPECT_EQ(s.at("spinewatch_tracking_lost_total{}"), 4);
  EXPECT_EQ(s.at("spinewatch_background_events_total{event=\"bootstrap\"}"), 2);
  EXPECT_EQ(s.at("spinewatch_stream_clients{}"), 3);
  EXPECT_EQ(s.at("spinewatch_stream_clients_dropped_total{reason=\"slow_or_flooding\"}"), 2);
  EXPECT_EQ(s.at("spinewatch_queue_depth{queue=\"pairs\"}"), 2);
  EXPECT_EQ(s.at("spinewatch_queue_capacity{queue=\"stream_inbox\"}"), 1024);
  EXPECT_EQ(s.at("spinewatch_http_stream_viewers{}"), 5);
  EXPECT_EQ(s.at("spinewatch_http_connections_dropped_total{reason=\"timeout\"}"), 7);
  // The histogram: cumulative buckets, +Inf = count, sum in seconds.
  EXPECT_EQ(s.at("spinewatch_pair_latency_seconds_bucket{le=\"0.00025\"}"), 0);
  EXPECT_EQ(s.at("spinewatch_pair_latency_seconds_bucket{le=\"0.0005\"}"), 2);
  EXPECT_EQ(s.at("spinewatch_pair_latency_seconds_bucket{le=\"0.001\"}"), 3);
  EXPECT_EQ(s.at("spinewatch_pair_latency_seconds_bucket{le=\"0.002\"}"), 4);
  EXPECT_EQ(s.at("spinewatch_pair_latency_seconds_bucket{le=\"+Inf\"}"), 5);
  EXPECT_EQ(s.at("spinewatch_pair_latency_seconds_count{}"), 5);
  EXPECT_NEAR(s.at("spinewatch_pair_latency_seconds_sum{}"), 0.0631, 1e-9);
  EXPECT_NE(families.find("spinewatch_pair_latency_seconds histogram"), std::string::npos) << families;
  EXPECT_NE(families.find("counter"), std::string::npos) << families;
}

std::string validate_state(const std::string& json) {
  test::TempDir dir;
  test::write_file(dir / "state.json", json);
  const auto r = test::run_command("/usr/bin/python3 '" + test::source_path("tests/support/validate_json.py").string() +
                                   "' '" + test::source_path("docs").string() + "' state '" +
                                   (dir / "state.json").string() + "'");
  return r.exit_code == 0 ? std::string() : (r.output.empty() ? "validator failed to run" : r.output);
}

StationInfo sample_station() {
  return {.station = "s7", .source = "recording /x", .calibration = "default rig", .default_rig = true,
          .background_mode = BackgroundMode::Learn, .relearn_available = true, .fps = 5, .camera_pixels = false};
}

TEST(StateJson, BeforeTheFirstSampleAndWithATrackedOneValidAgainstTheSchema) {
  const std::string empty = state_json(sample_station(), sample_metrics(), nullptr, 1'000'000'000);
  EXPECT_EQ(validate_state(empty), "") << empty;
  const auto e = nlohmann::json::parse(empty);
  EXPECT_TRUE(e.at("posture").is_null());
  EXPECT_TRUE(e.at("state").is_null());

  LiveSummary s;
  s.posture = test::sample_tracking_posture();
  s.coverage[0] = {.pixels = 5000, .left = false, .right = false, .top = true, .bottom = false};
  s.coverage[1] = {.pixels = 4000};
  s.background[0] = BackgroundSource::Learnt;
  s.background[1] = BackgroundSource::Bootstrapped;
  s.taken_ns = 1'000'000'000;
  const std::string full = state_json(sample_station(), sample_metrics(), &s, 1'250'000'000);
  EXPECT_EQ(validate_state(full), "") << full;
  const auto j = nlohmann::json::parse(full);
  EXPECT_EQ(j.at("state"), "tracking");
  EXPECT_EQ(j.at("seq"), 17);
  EXPECT_NEAR(j.at("age_s").get<double>(), 0.25, 1e-9);
  EXPECT_EQ(j.at("views").at("frontal").at("subject"), "cut at top");
  EXPECT_EQ(j.at("views").at("frontal").at("whole"), false);
  EXPECT_EQ(j.at("views").at("lateral").at("subject"), "whole");
  EXPECT_EQ(j.at("views").at("lateral").at("background"), "bootstrapped");
  EXPECT_EQ(j.at("counters").at("frames_lateral"), 1006);
  EXPECT_EQ(j.at("counters").at("tracking_lost"), 4);
  EXPECT_EQ(j.at("posture").at("vertebrae").size(), 17u);

  // The schema is not a rubber stamp.
  auto broken = j;
  broken["views"]["frontal"]["subject"] = "somewhere";
  EXPECT_NE(validate_state(broken.dump()), "");
  broken = j;
  broken["counters"].erase("pairs");
  EXPECT_NE(validate_state(broken.dump()), "");
}

TEST(ViewCoverage, WholeCutAndNobody) {
  BitMask m(40, 30);
  EXPECT_EQ(view_coverage(m).describe(), "nobody");
  for (int y = 5; y < 25; ++y) m.set_span(y, 10, 20);
  EXPECT_TRUE(view_coverage(m).whole());
  EXPECT_EQ(view_coverage(m).describe(), "whole");
  for (int y = 0; y < 25; ++y) m.set_span(y, 0, 20);
  const auto c = view_coverage(m);
  EXPECT_FALSE(c.whole());
  EXPECT_TRUE(c.top && c.left && !c.right && !c.bottom);
  EXPECT_EQ(c.describe(), "cut at top, left");
  m.set(39, 29);
  EXPECT_EQ(view_coverage(m).describe(), "cut at top, bottom, left, right");
}

// The live view's mailbox: nothing is copied while nobody wants it; with a
// viewer, at most fps samples a second, each drawn into one JPEG of both
// views over a plain background; a /state-only request gets samples
// without pictures.
TEST(LiveView, SamplesOnlyWhenWantedAtMostFpsAndDrawsWithoutCameraPixels) {
  std::mutex mutex;
  std::vector<std::shared_ptr<const LiveFrame>> frames;
  LiveView live(CameraRig::default_rig(), LiveViewOptions{.fps = 4}, [&](std::shared_ptr<const LiveFrame> f) {
    std::lock_guard lock(mutex);
    frames.push_back(std::move(f));
  });
  const auto format = FrameFormat::packed(PixelFormat::GREY, 320, 240);
  FramePair pair;
  pair.frontal = Frame::owning(format, {}, std::vector<std::uint8_t>(320 * 240, 200));
  pair.lateral = Frame::owning(format, {}, std::vector<std::uint8_t>(320 * 240, 200));
  BitMask person(320, 240);
  for (int y = 60; y < 200; ++y) person.set_span(y, 140, 180);
  EstimatorTrace trace;
  trace.silhouette[0] = trace.silhouette[1] = &person;
  trace.background_source[0] = trace.background_source[1] = BackgroundSource::Learnt;
  const Posture posture = test::sample_tracking_posture();
  const auto count = [&] {
    std::lock_guard lock(mutex);
    return frames.size();
  };

  for (int i = 0; i < 50; ++i) live.offer(pair, posture, trace);
  EXPECT_EQ(live.stats().samples, 0u) << "copied while nobody watched";

  live.add_viewer();
  for (int i = 0; i < 50; ++i) live.offer(pair, posture, trace);  // well within 250 ms
  EXPECT_EQ(live.stats().samples, 1u) << "more than fps samples a second";
  std::this_thread::sleep_for(300ms);
  live.offer(pair, posture, trace);
  EXPECT_EQ(live.stats().samples, 2u);
  ASSERT_TRUE(test::eventually([&] { return count() == 2; }));
  live.remove_viewer();
  {
    std::lock_guard lock(mutex);
    const LiveFrame& f = *frames.back();
    ASSERT_TRUE(f.jpeg);
    EXPECT_EQ(f.summary.posture.seq, 17u);
    EXPECT_TRUE(f.summary.coverage[0].whole());
    EXPECT_EQ(f.summary.coverage[0].pixels, person.count());
    const cv::Mat image = cv::imdecode(cv::Mat(1, static_cast<int>(f.jpeg->size()), CV_8UC1,
                                               const_cast<char*>(f.jpeg->data())), cv::IMREAD_COLOR);
    ASSERT_EQ(image.cols, 1280);
    ASSERT_EQ(image.rows, 508);
    // Outside the silhouette the plain background, not the frames' grey 200;
    // inside it the flat silhouette grey.
    const auto near = [](const cv::Vec3b& p, int v) { return std::abs(p[0] - v) <= 8 && std::abs(p[1] - v) <= 8 && std::abs(p[2] - v) <= 8; };
    EXPECT_TRUE(near(image.at<cv::Vec3b>(400, 40), 48));
    EXPECT_TRUE(near(image.at<cv::Vec3b>(400, 680), 48));
    EXPECT_TRUE(near(image.at<cv::Vec3b>(2 * 150, 2 * 160), 110));
  }
  std::this_thread::sleep_for(300ms);
  live.want_state_until(monotonic_now_ns() + 1'000'000'000);
  live.offer(pair, posture, trace);
  ASSERT_TRUE(test::eventually([&] { return count() == 3; }));
  std::lock_guard lock(mutex);
  EXPECT_FALSE(frames.back()->jpeg) << "a /state request needs no picture";
  EXPECT_EQ(live.stats().frames, 2u);
}

// The server on its own io_context thread, with a live view nobody feeds.
class HttpServerTest : public ::testing::Test {
 protected:
  void SetUp() override { spdlog::set_level(spdlog::level::warn); }
  void TearDown() override {
    if (server_) server_->stop();
    work_.reset();
    io_.stop();
    if (thread_.joinable()) thread_.join();
    spdlog::set_level(spdlog::level::info);
  }
  void start(HttpOptions options, BackgroundMode background_mode = BackgroundMode::Learn) {
    options.endpoint = {"127.0.0.1", 0};
    live_ = std::make_unique<LiveView>(CameraRig::default_rig(), LiveViewOptions{}, [](auto) {});
    StationInfo station = sample_station();
    station.background_mode = background_mode;
    HttpHandlers handlers{.metrics = [] { return sample_metrics(); },
                          .relearn_background = [this, background_mode] {
                            ++relearns_;
                            return background_mode == BackgroundMode::Learn;
                          }};
    auto s = HttpServer::start(io_, options, handlers, station, *live_);
    ASSERT_TRUE(s) << s.error().message;
    server_ = std::move(s).value();
    thread_ = std::thread([this] { io_.run(); });
  }
  std::uint16_t port() const { return server_->port(); }

  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_{io_.get_executor()};
  std::unique_ptr<LiveView> live_;
  std::unique_ptr<HttpServer> server_;
  std::thread thread_;
  std::atomic<int> relearns_{0};
};

TEST_F(HttpServerTest, PageMetricsAndErrors) {
  start({});
  auto page = test::http_get(port(), "/");
  EXPECT_EQ(page.status, 200);
  EXPECT_EQ(page.headers["content-type"], "text/html; charset=utf-8");
  EXPECT_NE(page.body.find("id=\"spine-side\""), std::string::npos);
  // Self-contained: nothing fetched from elsewhere.
  EXPECT_EQ(page.body.find("http://"), std::string::npos);
  EXPECT_EQ(page.body.find("https://"), std::string::npos);
  EXPECT_NE(page.headers["content-security-policy"].find("default-src 'none'"), std::string::npos);

  auto metrics = test::http_get(port(), "/metrics");
  EXPECT_EQ(metrics.status, 200);
  EXPECT_EQ(metrics.headers["content-type"], "text/plain; version=0.0.4; charset=utf-8");
  EXPECT_NE(metrics.body.find("spinewatch_pairs_total 1000\n"), std::string::npos);
  EXPECT_EQ(metrics.headers.count("content-security-policy"), 0u) << "only the page a browser runs has a policy";

  auto missing = test::http_get(port(), "/nothing");
  EXPECT_EQ(missing.status, 404);
  EXPECT_EQ(missing.headers["content-type"], "text/plain");
  EXPECT_EQ(test::http_get(port(), "/?action=nothing").status, 404);
  const auto wrong = test::http_request(port(), "POST", "/metrics");
  EXPECT_EQ(wrong.status, 405);
  EXPECT_EQ(wrong.headers.at("allow"), "GET");
  EXPECT_EQ(test::http_request(port(), "GET", "/background/relearn").status, 405);
}

TEST_F(HttpServerTest, MalformedAndOversizedRequestsAreAnsweredClosedAndCounted) {
  start({.max_header_bytes = 4096});
  {
    test::HttpConnection c(port());
    c.send("THIS IS NOT HTTP\r\n\r\n");
    auto head = c.read_head(5s);
    ASSERT_TRUE(head);
    EXPECT_EQ(test::parse_head(*head).status, 400);
    EXPECT_TRUE(c.wait_closed(5s));
  }
  {
    test::HttpConnection c(port());
    c.send("GET / HTTP/1.1\r\nHost: x\r\nX-Big: " + std::string(16 * 1024, 'a') + "\r\n\r\n");
    auto head = c.read_head(5s);
    ASSERT_TRUE(head);
    EXPECT_EQ(test::parse_head(*head).status, 431);
    EXPECT_TRUE(c.wait_closed(5s));
  }
  {
    test::HttpConnection c(port());
    c.send("POST /background/relearn HTTP/1.1\r\nHost: x\r\nContent-Length: 100000\r\n\r\n");
    auto head = c.read_head(5s);
    ASSERT_TRUE(head);
    EXPECT_EQ(test::parse_head(*head).status, 413);
  }
  EXPECT_TRUE(test::eventually([&] { return server_->stats().bad_requests == 3; })) << server_->stats().bad_requests;
  EXPECT_EQ(relearns_, 0) << "a refused request reached its handler";
  // And the server still answers.
  EXPECT_EQ(test::http_get(port(), "/metrics").status, 200);
}

TEST_F(HttpServerTest, AnUnfinishedRequestIsCutAfterTheTimeoutAnIdleOneIsNotCounted) {
  start({.timeout = 300ms});
  test::HttpConnection slow(port());
  slow.send("GET /metrics HTTP/1.1\r\nHo");  // and nothing more
  test::HttpConnection idle(port());         // sends nothing at all
  EXPECT_TRUE(slow.wait_closed(3s));
  EXPECT_TRUE(idle.wait_closed(3s));
  EXPECT_TRUE(test::eventually([&] { return server_->stats().connections == 0; }));
  EXPECT_EQ(server_->stats().timed_out, 1u);
}

TEST_F(HttpServerTest, ConnectionsBeyondTheLimitGet503AndAreCounted) {
  start({.max_connections = 4});
  std::vector<test::HttpConnection> open;
  for (int i = 0; i < 4; ++i) open.emplace_back(port());
  ASSERT_TRUE(test::eventually([&] { return server_->stats().connections == 4; }));
  test::HttpConnection extra(port());
  auto head = extra.read_head(5s);
  ASSERT_TRUE(head);
  EXPECT_EQ(test::parse_head(*head).status, 503);
  EXPECT_TRUE(extra.wait_closed(5s));
  EXPECT_EQ(server_->stats().rejected, 1u);
  open.clear();
  EXPECT_TRUE(test::eventually([&] { return server_->stats().connections == 0; }));
  EXPECT_EQ(test::http_get(port(), "/metrics").status, 200);
}

TEST_F(HttpServerTest, KeepAliveServesSeveralRequestsOnOneConnection) {
  start({});
  test::HttpConnection c(port());
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(c.send("GET /metrics HTTP/1.1\r\nHost: x\r\n\r\n"));
    auto head = c.read_head(5s);
    ASSERT_TRUE(head) << "request " << i;
    const auto r = test::parse_head(*head);
    EXPECT_EQ(r.status, 200);
    const auto n = std::stoul(r.headers.at("content-length"));
    ASSERT_TRUE(c.receive_at_least(n, 5s));
    c.take(n);
  }
  EXPECT_EQ(server_->stats().connections_total, 1u);
}

TEST_F(HttpServerTest, StateWithoutSamplesAnswersAfterItsWaitWithNullPosture) {
  start({});
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = test::http_get(port(), "/state");
  EXPECT_EQ(r.status, 200);
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 1s) << "it waited for a sample first";
  EXPECT_EQ(validate_state(r.body), "") << r.body;
  EXPECT_TRUE(nlohmann::json::parse(r.body).at("posture").is_null());
}

TEST_F(HttpServerTest, RelearnIsAPostThatReachesTheDaemonOnlyInLearnMode) {
  start({});
  const auto r = test::http_request(port(), "POST", "/background/relearn");
  EXPECT_EQ(r.status, 202);
  EXPECT_EQ(nlohmann::json::parse(r.body).at("relearn"), true);
  EXPECT_EQ(relearns_, 1);
}

TEST_F(HttpServerTest, RelearnRefusedWithAStoredImageMode) {
  start({}, BackgroundMode::Image);
  const auto r = test::http_request(port(), "POST", "/background/relearn");
  EXPECT_EQ(r.status, 409);
  EXPECT_NE(r.body.find("spinewatch background"), std::string::npos);
}

}  // namespace
}  // namespace spinewatch
