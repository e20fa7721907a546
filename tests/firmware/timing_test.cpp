// Timing arithmetic and the EEPROM image, built for the host from the
// firmware's own C sources.
#include <gtest/gtest.h>

#include <cstring>

extern "C" {
#include "trig_crc16.h"
#include "trig_eeprom_image.h"
#include "trig_timing.h"
}

namespace {

trig_settings settings(std::uint32_t rate_mhz, std::uint32_t width, std::uint32_t da = 0, std::uint32_t db = 0) {
  trig_settings s{};
  s.rate_mhz = rate_mhz;
  s.width_us = width;
  s.delay_us[TRIG_CH_A] = da;
  s.delay_us[TRIG_CH_B] = db;
  return s;
}

bool valid(const trig_settings& s) { return trig_validate(&s) == nullptr; }

TEST(TriggerTiming, RateBoundaries) {
  EXPECT_TRUE(valid(settings(1000, 1000)));
  EXPECT_TRUE(valid(settings(120000, 1000)));
  EXPECT_FALSE(valid(settings(999, 1000)));
  EXPECT_FALSE(valid(settings(120001, 1000)));
  const trig_settings zero = settings(0, 1000);
  EXPECT_STREQ(trig_validate(&zero), "rate out of range (1-120 Hz)");
}

TEST(TriggerTiming, WidthBoundaries) {
  // 120 Hz: period 8333 us, so the widest pulse is 8233 us.
  EXPECT_TRUE(valid(settings(120000, 20)));
  EXPECT_FALSE(valid(settings(120000, 19)));
  EXPECT_TRUE(valid(settings(120000, 8233)));
  EXPECT_FALSE(valid(settings(120000, 8234)));
  // 1 Hz: period 1 s.
  EXPECT_TRUE(valid(settings(1000, 999900)));
  EXPECT_FALSE(valid(settings(1000, 999901)));
}

TEST(TriggerTiming, DelayMustLeaveThePulseInsideThePeriod) {
  EXPECT_TRUE(valid(settings(120000, 1000, 0, 7233)));
  EXPECT_FALSE(valid(settings(120000, 1000, 0, 7234)));
  EXPECT_FALSE(valid(settings(120000, 1000, 7234, 0)));
  EXPECT_FALSE(valid(settings(120000, 1000, 0xFFFFFFFFu, 0)));  // no wrap-around in the sum
}

TEST(TriggerTiming, TicksFromSettings) {
  trig_timing t{};
  auto s = settings(30000, 1000, 0, 250);
  trig_compute(&s, &t);
  EXPECT_EQ(t.period_ticks, 66666u);  // 2 MHz / 30 Hz = 66666.67
  EXPECT_EQ(t.period_frac, 20000u);   // .667 of a tick, in rate_mhz units
  EXPECT_EQ(t.width_ticks, 2000u);
  EXPECT_EQ(t.delay_ticks[TRIG_CH_A], 0u);
  EXPECT_EQ(t.delay_ticks[TRIG_CH_B], 500u);
  s = settings(1000, 20);
  trig_compute(&s, &t);
  EXPECT_EQ(t.period_ticks, 2000000u);
  EXPECT_EQ(t.period_frac, 0u);
  EXPECT_EQ(t.width_ticks, 40u);
  s = settings(120000, 8233);
  trig_compute(&s, &t);
  EXPECT_EQ(t.period_ticks, 16666u);
  EXPECT_EQ(t.period_frac, 80000u);
}

TEST(TriggerTiming, BresenhamPeriodsAverageToTheExactRate) {
  // Fractional rates: each period is floor or floor+1 ticks, and N periods
  // sum to N * exact within one tick.
  for (std::uint32_t rate : {1000u, 29970u, 30000u, 59940u, 120000u, 7777u}) {
    trig_timing t{};
    auto s = settings(rate, 100);
    trig_compute(&s, &t);
    std::uint64_t total = 0;
    std::uint32_t acc = 0;
    const int n = 1000;
    for (int i = 0; i < n; ++i) {
      std::uint32_t p = t.period_ticks;
      acc += t.period_frac;
      if (acc >= rate) {
        acc -= rate;
        ++p;
      }
      EXPECT_TRUE(p == t.period_ticks || p == t.period_ticks + 1);
      total += p;
    }
    const double exact = 2e9 / rate * n;
    EXPECT_NEAR(static_cast<double>(total), exact, 1.0) << rate;
  }
}

TEST(TriggerCrc16, MatchesPublishedCheckValues) {
  const char* check = "123456789";
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(check);
  EXPECT_EQ(trig_crc16(0x0000, bytes, 9), 0xBB3D);  // CRC-16/ARC
  EXPECT_EQ(trig_crc16(0xFFFF, bytes, 9), 0x4B37);  // CRC-16/MODBUS
}

TEST(TriggerEepromImage, RoundTripsAndRejectsDamage) {
  trig_state st{};
  st.settings = settings(59940, 1234, 10, 500);
  st.running = 0;
  std::uint8_t image[TRIG_EEPROM_SIZE];
  trig_eeprom_encode(&st, image);
  trig_state back{};
  ASSERT_EQ(trig_eeprom_decode(image, &back), 1);
  EXPECT_EQ(back.settings.rate_mhz, 59940u);
  EXPECT_EQ(back.settings.width_us, 1234u);
  EXPECT_EQ(back.settings.delay_us[TRIG_CH_B], 500u);
  EXPECT_EQ(back.running, 0);

  for (std::size_t i = 0; i < TRIG_EEPROM_SIZE; ++i) {
    std::uint8_t damaged[TRIG_EEPROM_SIZE];
    std::memcpy(damaged, image, sizeof damaged);
    damaged[i] ^= 0x10;
    trig_state untouched{};
    untouched.settings.rate_mhz = 7;
    EXPECT_EQ(trig_eeprom_decode(damaged, &untouched), 0) << "byte " << i;
    EXPECT_EQ(untouched.settings.rate_mhz, 7u);
  }
  std::uint8_t blank[TRIG_EEPROM_SIZE];
  std::memset(blank, 0xFF, sizeof blank);
  EXPECT_EQ(trig_eeprom_decode(blank, &back), 0);
}

TEST(TriggerEepromImage, IntactButOutOfRangeIsRejected) {
  trig_state st{};
  st.settings = settings(500, 1000);  // 0.5 Hz: never valid
  std::uint8_t image[TRIG_EEPROM_SIZE];
  trig_eeprom_encode(&st, image);
  EXPECT_EQ(trig_eeprom_decode(image, &st), 0);
}

}  // namespace
