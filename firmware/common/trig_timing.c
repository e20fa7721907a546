#include "trig_timing.h"

#include <stddef.h>

void trig_default_settings(trig_settings *s) {
  s->rate_mhz = TRIG_DEFAULT_RATE_MHZ;
  s->width_us = TRIG_DEFAULT_WIDTH_US;
  s->delay_us[TRIG_CH_A] = 0;
  s->delay_us[TRIG_CH_B] = 0;
}

uint32_t trig_period_us(uint32_t rate_mhz) { return 1000000000UL / rate_mhz; }

const char *trig_validate(const trig_settings *s) {
  if (s->rate_mhz < TRIG_RATE_MIN_MHZ || s->rate_mhz > TRIG_RATE_MAX_MHZ) return "rate out of range (1-120 Hz)";
  if (s->width_us < TRIG_WIDTH_MIN_US) return "width below 20 us";
  /* Widths and delays are bounded by the period (<= 1 s) before they are
   * added, so the sums below cannot overflow. */
  const uint32_t usable = trig_period_us(s->rate_mhz) - TRIG_GUARD_US;
  if (s->width_us > usable) return "width above period - 100 us";
  for (int ch = 0; ch < TRIG_CHANNELS; ++ch) {
    if (s->delay_us[ch] > usable || s->delay_us[ch] + s->width_us > usable)
      return "delay + width above period - 100 us";
  }
  return NULL;
}

void trig_compute(const trig_settings *s, trig_timing *t) {
  /* TRIG_TICK_HZ * 1000 = 2e9 fits in 32 bits. */
  const uint32_t num = TRIG_TICK_HZ * 1000UL;
  t->rate_mhz = s->rate_mhz;
  t->period_ticks = num / s->rate_mhz;
  t->period_frac = num % s->rate_mhz;
  t->width_ticks = s->width_us * TRIG_TICKS_PER_US;
  for (int ch = 0; ch < TRIG_CHANNELS; ++ch) t->delay_ticks[ch] = s->delay_us[ch] * TRIG_TICKS_PER_US;
}
