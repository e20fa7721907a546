// The line protocol, built for the host from the firmware's own C sources:
// every command, every error path, line assembly and resynchronisation.
#include <gtest/gtest.h>

#include <string>

extern "C" {
#include "trig_protocol.h"
}

namespace {

class Protocol : public ::testing::Test {
 protected:
  Protocol() {
    trig_default_settings(&st.settings);
    st.running = 0;
  }

  std::string handle(const std::string& line) {
    char reply[TRIG_REPLY_MAX];
    actions = trig_handle_line(&st, line.c_str(), &live, reply, sizeof reply);
    return reply;
  }

  trig_state st{};
  trig_live live{1234, 56789};
  std::uint8_t actions = 0;
};

TEST_F(Protocol, VersionNamesFirmwareAndProtocol) {
  EXPECT_EQ(handle("VERSION"), "OK spinewatch-trigger 1.0.0 proto=1");
  EXPECT_EQ(actions, TRIG_ACT_NONE);
}

TEST_F(Protocol, StatusReportsEveryField) {
  EXPECT_EQ(handle("STATUS"), "OK rate=30.000 width=1000 delay_a=0 delay_b=0 running=0 count=1234 uptime_ms=56789");
  live = {4294967295u, 4294967295u};
  handle("CONFIG 119.999 999 7000 7233");
  EXPECT_EQ(handle("status"),
            "OK rate=119.999 width=999 delay_a=7000 delay_b=7233 running=0 count=4294967295 uptime_ms=4294967295");
}

TEST_F(Protocol, RateAcceptsUpToThreeFractionDigits) {
  EXPECT_EQ(handle("RATE 29.97"), "OK");
  EXPECT_EQ(actions, TRIG_ACT_APPLY);
  EXPECT_EQ(st.settings.rate_mhz, 29970u);
  EXPECT_EQ(handle("RATE 1"), "OK");
  EXPECT_EQ(st.settings.rate_mhz, 1000u);
  EXPECT_EQ(handle("RATE 120.000"), "OK");
  EXPECT_EQ(st.settings.rate_mhz, 120000u);
  EXPECT_EQ(handle("RATE 60.0001"), "ERR bad number");
  EXPECT_EQ(st.settings.rate_mhz, 120000u);
}

TEST_F(Protocol, RateRangeIsEnforced) {
  EXPECT_EQ(handle("RATE 0.999"), "ERR rate out of range (1-120 Hz)");
  EXPECT_EQ(handle("RATE 120.001"), "ERR rate out of range (1-120 Hz)");
  EXPECT_EQ(handle("RATE 4294967"), "ERR rate out of range (1-120 Hz)");
  EXPECT_EQ(handle("RATE 99999999999"), "ERR bad number");
  // Seven integer digits and three decimals are ten digits in milli-hertz,
  // past 32 bits: refused, not wrapped to 1000 mHz (it was taken as 1 Hz).
  EXPECT_EQ(handle("RATE 4294968.296"), "ERR bad number");
  EXPECT_EQ(handle("CONFIG 4294997.296 1000 0 0"), "ERR bad number");
  EXPECT_EQ(actions, TRIG_ACT_NONE);
  EXPECT_EQ(st.settings.rate_mhz, 30000u);
}

TEST_F(Protocol, BadNumbers) {
  for (const char* line : {"RATE abc", "RATE -5", "RATE 3x", "RATE .5", "RATE 5.", "WIDTH 1.5", "WIDTH 0x10",
                           "DELAY A -1", "CONFIG 30 1000 0 b"})
    EXPECT_EQ(handle(line), "ERR bad number") << line;
  EXPECT_EQ(st.settings.width_us, 1000u);
}

TEST_F(Protocol, WidthLimitsFollowTheRate) {
  EXPECT_EQ(handle("WIDTH 20"), "OK");
  EXPECT_EQ(handle("WIDTH 19"), "ERR width below 20 us");
  EXPECT_EQ(handle("WIDTH 33233"), "OK");  // 30 Hz: period 33333 us
  EXPECT_EQ(handle("WIDTH 33234"), "ERR width above period - 100 us");
  // A faster rate that no longer fits the current width is refused.
  EXPECT_EQ(handle("RATE 120"), "ERR width above period - 100 us");
  EXPECT_EQ(st.settings.rate_mhz, 30000u);
}

TEST_F(Protocol, DelayPerChannel) {
  EXPECT_EQ(handle("DELAY B 250"), "OK");
  EXPECT_EQ(st.settings.delay_us[TRIG_CH_B], 250u);
  EXPECT_EQ(handle("delay a 100"), "OK");
  EXPECT_EQ(st.settings.delay_us[TRIG_CH_A], 100u);
  EXPECT_EQ(handle("DELAY C 1"), "ERR channel must be A or B");
  EXPECT_EQ(handle("DELAY A 32234"), "ERR delay + width above period - 100 us");
  EXPECT_EQ(handle("DELAY A 32233"), "OK");
  EXPECT_EQ(handle("DELAY A"), "ERR usage: DELAY <A|B> <us>");
}

TEST_F(Protocol, ConfigSetsEverythingAtOnceOrNothing) {
  EXPECT_EQ(handle("CONFIG 120 5000 0 100"), "OK");
  EXPECT_EQ(actions, TRIG_ACT_APPLY);
  EXPECT_EQ(st.settings.rate_mhz, 120000u);
  EXPECT_EQ(st.settings.width_us, 5000u);
  EXPECT_EQ(st.settings.delay_us[TRIG_CH_B], 100u);
  EXPECT_EQ(handle("CONFIG 1 999900 0 1"), "ERR delay + width above period - 100 us");
  EXPECT_EQ(st.settings.rate_mhz, 120000u);
  EXPECT_EQ(handle("CONFIG 1 2 3"), "ERR usage: CONFIG <hz> <width_us> <delay_a_us> <delay_b_us>");
  EXPECT_EQ(handle("CONFIG 1 2 3 4 5"), "ERR too many arguments");
}

TEST_F(Protocol, StartStopSaveDefaults) {
  EXPECT_EQ(handle("START"), "OK");
  EXPECT_EQ(actions, TRIG_ACT_START);
  EXPECT_EQ(st.running, 1);
  EXPECT_EQ(handle("STOP"), "OK");
  EXPECT_EQ(actions, TRIG_ACT_STOP);
  EXPECT_EQ(st.running, 0);
  EXPECT_EQ(handle("SAVE"), "OK");
  EXPECT_EQ(actions, TRIG_ACT_SAVE);
  handle("CONFIG 60 50 1 2");
  EXPECT_EQ(handle("DEFAULTS"), "OK");
  EXPECT_EQ(actions, TRIG_ACT_APPLY);
  EXPECT_EQ(st.settings.rate_mhz, 30000u);
  EXPECT_EQ(st.settings.width_us, 1000u);
  EXPECT_EQ(st.settings.delay_us[TRIG_CH_A], 0u);
  EXPECT_EQ(handle("START now"), "ERR unexpected argument");
  EXPECT_EQ(st.running, 0);
}

TEST_F(Protocol, MalformedLines) {
  EXPECT_EQ(handle(""), "ERR empty line");
  EXPECT_EQ(handle("   "), "ERR empty line");
  EXPECT_EQ(handle("FOO"), "ERR unknown command");
  EXPECT_EQ(handle("\x01\xff"), "ERR unknown command");
  EXPECT_EQ(handle("RATES 30"), "ERR unknown command");
  EXPECT_EQ(handle("RATE"), "ERR usage: RATE <hz>");
  EXPECT_EQ(handle("RATE 30 40"), "ERR usage: RATE <hz>");
  EXPECT_EQ(actions, TRIG_ACT_NONE);
}

TEST_F(Protocol, ReplyIsTruncatedNotOverrun) {
  char small[8];
  trig_handle_line(&st, "VERSION", &live, small, sizeof small);
  EXPECT_EQ(std::string(small), "OK spin");
}

TEST(TriggerMhz, Formatting) {
  char out[16];
  trig_format_mhz(1000, out, sizeof out);
  EXPECT_STREQ(out, "1.000");
  trig_format_mhz(29970, out, sizeof out);
  EXPECT_STREQ(out, "29.970");
  trig_format_mhz(120005, out, sizeof out);
  EXPECT_STREQ(out, "120.005");
  trig_format_mhz(1050, out, sizeof out);
  EXPECT_STREQ(out, "1.050");
}

std::vector<std::pair<trig_line_result, std::string>> feed(trig_linebuf& lb, const std::string& bytes) {
  std::vector<std::pair<trig_line_result, std::string>> out;
  for (char c : bytes) {
    const trig_line_result r = trig_linebuf_push(&lb, c);
    if (r != TRIG_LINE_PENDING) out.emplace_back(r, r == TRIG_LINE_READY ? std::string(lb.buf) : std::string());
  }
  return out;
}

TEST(TriggerLineBuffer, SplitsLinesAndStripsCarriageReturns) {
  trig_linebuf lb;
  trig_linebuf_init(&lb);
  const auto lines = feed(lb, "RATE 30\r\nSTATUS\n\n");
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].second, "RATE 30");
  EXPECT_EQ(lines[1].second, "STATUS");
  EXPECT_EQ(lines[2].first, TRIG_LINE_READY);
  EXPECT_EQ(lines[2].second, "");
}

TEST(TriggerLineBuffer, MaximumLengthBoundary) {
  trig_linebuf lb;
  trig_linebuf_init(&lb);
  const std::string max(TRIG_LINE_MAX, 'x');
  auto lines = feed(lb, max + "\n" + max + "\r\n" + max + "y\n" + max + "y\r\n");
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0].first, TRIG_LINE_READY);
  EXPECT_EQ(lines[0].second, max);
  EXPECT_EQ(lines[1].first, TRIG_LINE_READY);
  EXPECT_EQ(lines[1].second, max);
  EXPECT_EQ(lines[2].first, TRIG_LINE_TOO_LONG);
  EXPECT_EQ(lines[3].first, TRIG_LINE_TOO_LONG);
}

TEST(TriggerLineBuffer, ResynchronisesAfterALongLine) {
  trig_linebuf lb;
  trig_linebuf_init(&lb);
  // Appended, not `std::string(500, 'z') + "…"`: GCC 12 at -O1 (the tests'
  // level) warns falsely on that temporary's move (-Warray-bounds).
  std::string input(500, 'z');
  input += "\nVERSION\n";
  const auto lines = feed(lb, input);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].first, TRIG_LINE_TOO_LONG);
  EXPECT_EQ(lines[1].first, TRIG_LINE_READY);
  EXPECT_EQ(lines[1].second, "VERSION");
}

}  // namespace
