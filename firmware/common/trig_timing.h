/* Trigger settings and the timer arithmetic behind them.
 *
 * Pure C99 with no AVR headers: compiled by avr-gcc into the firmware and
 * by the host compiler for the unit tests, so both agree by construction.
 *
 * Timer1 runs free (normal mode) at F_CPU / 8 = 2 MHz, one tick = 0.5 us,
 * for every rate: periods longer than the 16-bit counter are reached in
 * software "hops" (see firmware/src/pulse.c), so no prescaler ever changes
 * while pulses run and every rate has the same 0.5 us resolution. */
#ifndef TRIG_TIMING_H
#define TRIG_TIMING_H

#include <stdint.h>

#define TRIG_F_CPU 16000000UL
#define TRIG_PRESCALER 8UL
#define TRIG_TICK_HZ (TRIG_F_CPU / TRIG_PRESCALER) /* 2 MHz */
#define TRIG_TICKS_PER_US (TRIG_TICK_HZ / 1000000UL)

#define TRIG_RATE_MIN_MHZ 1000UL   /* 1 Hz, in milli-hertz */
#define TRIG_RATE_MAX_MHZ 120000UL /* 120 Hz */
#define TRIG_WIDTH_MIN_US 20UL
#define TRIG_GUARD_US 100UL /* idle time at the end of every period */

#define TRIG_DEFAULT_RATE_MHZ 30000UL
#define TRIG_DEFAULT_WIDTH_US 1000UL

enum { TRIG_CH_A = 0, TRIG_CH_B = 1, TRIG_CHANNELS = 2 };

typedef struct {
  uint32_t rate_mhz;                /* pulse rate, milli-hertz */
  uint32_t width_us;                /* pulse width = exposure on pulse-width sensors */
  uint32_t delay_us[TRIG_CHANNELS]; /* each camera's pulse start after the period start */
} trig_settings;

/* What the pulse generator needs, in timer ticks. The exact period is
 * period_ticks + period_frac / rate_mhz ticks: the fraction is spread over
 * the periods (Bresenham), so a single period is within one tick and the
 * long-run rate is exact to the crystal. */
typedef struct {
  uint32_t period_ticks;
  uint32_t period_frac; /* remainder of TRIG_TICK_HZ * 1000 / rate_mhz */
  uint32_t rate_mhz;
  uint32_t width_ticks;
  uint32_t delay_ticks[TRIG_CHANNELS];
} trig_timing;

void trig_default_settings(trig_settings *s);

/* The period in whole microseconds (rounded down). */
uint32_t trig_period_us(uint32_t rate_mhz);

/* NULL when the settings are usable, else the reason (for an "ERR ..." line). */
const char *trig_validate(const trig_settings *s);

/* Valid settings only (call trig_validate first). */
void trig_compute(const trig_settings *s, trig_timing *t);

#endif
