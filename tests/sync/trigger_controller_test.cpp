// The host client against a fake controller on a pseudo-terminal. The fake
// runs the firmware's own protocol code (firmware/common, built for the
// host), so a client that works here speaks what the device speaks.
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "spinewatch/sync/trigger_controller.hpp"

extern "C" {
#include "trig_protocol.h"
}

namespace spinewatch::sync {
namespace {

using namespace std::chrono_literals;

// Answers like the firmware; `rewrite` may replace or drop (nullopt) a reply.
class FakeController {
 public:
  using Rewrite = std::function<std::optional<std::string>(const std::string& line, const std::string& reply)>;

  explicit FakeController(Rewrite rewrite = {}) : rewrite_(std::move(rewrite)) {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY);
    if (master_ < 0 || ::grantpt(master_) != 0 || ::unlockpt(master_) != 0) std::abort();
    device_ = ::ptsname(master_);
    trig_default_settings(&state_.settings);
    state_.running = 0;
    trig_linebuf_init(&line_);
    thread_ = std::thread([this] { run(); });
  }
  ~FakeController() {
    stop_ = true;
    thread_.join();
    ::close(master_);
  }

  const std::string& device() const { return device_; }
  std::vector<std::string> received() {
    std::lock_guard lock(mutex_);
    return received_;
  }
  trig_state state() {
    std::lock_guard lock(mutex_);
    return state_;
  }

 private:
  void run() {
    while (!stop_) {
      pollfd p{master_, POLLIN, 0};
      const int ready = ::poll(&p, 1, 20);
      if (ready <= 0) continue;
      if (!(p.revents & POLLIN)) {  // POLLHUP while no one has the slave open
        std::this_thread::sleep_for(5ms);
        continue;
      }
      char bytes[256];
      const ssize_t n = ::read(master_, bytes, sizeof bytes);
      if (n <= 0) {
        std::this_thread::sleep_for(5ms);  // EIO while no one has the slave open
        continue;
      }
      for (ssize_t i = 0; i < n; ++i) {
        if (trig_linebuf_push(&line_, bytes[i]) != TRIG_LINE_READY) continue;
        handle(line_.buf);
      }
    }
  }

  void handle(const std::string& line) {
    char reply[TRIG_REPLY_MAX];
    {
      std::lock_guard lock(mutex_);
      received_.push_back(line);
      const trig_live live{static_cast<std::uint32_t>(received_.size()), 4321};
      trig_handle_line(&state_, line.c_str(), &live, reply, sizeof reply);
    }
    std::optional<std::string> out = std::string(reply);
    if (rewrite_) out = rewrite_(line, *out);
    if (!out) return;
    const std::string bytes = *out + "\r\n";
    if (::write(master_, bytes.data(), bytes.size()) != static_cast<ssize_t>(bytes.size())) std::abort();
  }

  Rewrite rewrite_;
  int master_ = -1;
  std::string device_;
  std::mutex mutex_;
  trig_state state_{};
  trig_linebuf line_{};
  std::vector<std::string> received_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TriggerController::Options quick() { return {.reply_timeout = 300ms, .boot_wait = 0ms}; }

TEST(TriggerController, OpensChecksVersionConfiguresAndStarts) {
  FakeController fake;
  auto controller = TriggerController::open(fake.device(), quick());
  ASSERT_TRUE(controller) << controller.error().message;
  auto version = (*controller)->version();
  ASSERT_TRUE(version) << version.error().message;
  EXPECT_EQ(version->firmware, "1.0.0");
  EXPECT_EQ(version->protocol, 1);

  ASSERT_TRUE((*controller)->configure({.rate_hz = 59.94, .width_us = 800, .delay_a_us = 0, .delay_b_us = 120}));
  ASSERT_TRUE((*controller)->start());
  auto status = (*controller)->status();
  ASSERT_TRUE(status) << status.error().message;
  EXPECT_DOUBLE_EQ(status->rate_hz, 59.94);
  EXPECT_EQ(status->width_us, 800);
  EXPECT_EQ(status->delay_b_us, 120);
  EXPECT_TRUE(status->running);
  EXPECT_EQ(status->uptime_ms, 4321u);
  EXPECT_EQ(fake.state().settings.rate_mhz, 59940u);
  EXPECT_EQ(fake.received()[2], "CONFIG 59.940 800 0 120");
  EXPECT_EQ(describe(*status), "59.940 Hz, 800 us, delays 0/120 us, running, 5 pulses, up 4 s");

  ASSERT_TRUE((*controller)->stop());
  EXPECT_FALSE((*controller)->status()->running);
}

TEST(TriggerController, ControllerErrorsCarryTheReason) {
  FakeController fake;
  auto controller = TriggerController::open(fake.device(), quick());
  ASSERT_TRUE(controller);
  auto s = (*controller)->configure({.rate_hz = 200, .width_us = 1000});
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().message, "trigger controller " + fake.device() +
                                   ": CONFIG 200.000 1000 0 0: rate out of range (1-120 Hz)");
  s = (*controller)->configure({.rate_hz = 120, .width_us = 9000});
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("width above period - 100 us"), std::string::npos);
  EXPECT_EQ(fake.state().settings.rate_mhz, 30000u) << "a refused CONFIG changes nothing";
  // The line stays in step after errors.
  EXPECT_TRUE((*controller)->status());
}

TEST(TriggerController, NoReplyIsATimeoutNotAHang) {
  FakeController fake([](const std::string&, const std::string&) { return std::nullopt; });
  const auto t0 = std::chrono::steady_clock::now();
  auto controller = TriggerController::open(fake.device(), quick());
  const auto took = std::chrono::steady_clock::now() - t0;
  ASSERT_FALSE(controller);
  EXPECT_NE(controller.error().message.find("VERSION: no reply within 300 ms"), std::string::npos)
      << controller.error().message;
  EXPECT_LT(took, 2s);
}

TEST(TriggerController, BootWaitRetriesUntilTheControllerAnswers) {
  std::atomic<int> asked{0};
  FakeController fake([&](const std::string&, const std::string& reply) -> std::optional<std::string> {
    if (++asked <= 2) return std::nullopt;  // still in the bootloader
    return reply;
  });
  auto controller = TriggerController::open(fake.device(), {.reply_timeout = 100ms, .boot_wait = 1000ms});
  ASSERT_TRUE(controller) << controller.error().message;
  EXPECT_EQ(asked.load(), 3);
}

TEST(TriggerController, GarbageAndWrongProtocolAreRefused) {
  {
    FakeController fake([](const std::string&, const std::string&) { return std::string("\x7f\x01 hello"); });
    auto controller = TriggerController::open(fake.device(), quick());
    ASSERT_FALSE(controller);
    EXPECT_NE(controller.error().message.find("unexpected reply"), std::string::npos) << controller.error().message;
  }
  {
    FakeController fake([](const std::string& line, const std::string& reply) -> std::optional<std::string> {
      if (line == "VERSION") return "OK spinewatch-trigger 2.0.0 proto=2";
      return reply;
    });
    auto controller = TriggerController::open(fake.device(), quick());
    ASSERT_FALSE(controller);
    EXPECT_NE(controller.error().message.find("speaks protocol 2, spinewatch speaks 1"), std::string::npos)
        << controller.error().message;
  }
  {
    FakeController fake([](const std::string& line, const std::string& reply) -> std::optional<std::string> {
      if (line == "STATUS") return "OK rate=fast";
      return reply;
    });
    auto controller = TriggerController::open(fake.device(), quick());
    ASSERT_TRUE(controller);
    auto status = (*controller)->status();
    ASSERT_FALSE(status);
    EXPECT_NE(status.error().message.find("not a STATUS reply: 'OK rate=fast'"), std::string::npos);
  }
}

TEST(TriggerController, MissingDeviceIsOneClearError) {
  auto controller = TriggerController::open("/dev/does-not-exist-spinewatch", quick());
  ASSERT_FALSE(controller);
  EXPECT_EQ(controller.error().message,
            "trigger controller /dev/does-not-exist-spinewatch: cannot open: No such file or directory");
}

TEST(TriggerReplies, ParseStatusAndVersion) {
  auto s = parse_trigger_status("OK rate=30.000 width=1000 delay_a=0 delay_b=5 running=1 count=9 uptime_ms=77");
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(s->rate_hz, 30.0);
  EXPECT_EQ(s->delay_b_us, 5);
  EXPECT_EQ(s->count, 9u);
  EXPECT_FALSE(parse_trigger_status("OK rate=30.000 width=1000 delay_a=0 delay_b=5 running=2 count=9 uptime_ms=77"));
  EXPECT_FALSE(parse_trigger_status("OK rate=30.000 width=1000"));
  EXPECT_FALSE(parse_trigger_status("ERR rate=30.000 width=1000 delay_a=0 delay_b=5 running=1 count=9 uptime_ms=77"));
  auto v = parse_trigger_version("OK spinewatch-trigger 1.2.3 proto=1");
  ASSERT_TRUE(v);
  EXPECT_EQ(v->firmware, "1.2.3");
  EXPECT_FALSE(parse_trigger_version("OK other-box 1.0 proto=1"));
  EXPECT_FALSE(parse_trigger_version("OK spinewatch-trigger 1.0.0"));
}

}  // namespace
}  // namespace spinewatch::sync
