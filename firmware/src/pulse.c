#include "pulse.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>

/* How edges are made: Timer1 counts freely through 0..65535 at 2 MHz. Each
 * channel's next edge is an absolute 32-bit tick; its compare unit is set
 * to "set OC1x on match" (rising edge) or "clear on match" (falling edge),
 * so the pin changes in hardware on the exact tick, whatever the CPU is
 * doing. The compare ISR then only prepares the following edge, which is
 * at least 20 us (a pulse) or 100 us (the guard) away. Edges further than
 * the 16-bit counter reaches are approached in hops of HOP ticks with the
 * pin disconnected from the compare unit (COM = 0, pin stays low). */

#define HOP 32768U
#define START_LEAD_TICKS (100U * TRIG_TICKS_PER_US)
#define SYNC_PORT PORTD
#define SYNC_DDR DDRD
#define SYNC_BIT PD7

enum { WAIT_RISE, WAIT_FALL, DONE };
enum { COM_OFF = 0, COM_CLEAR = 2, COM_SET = 3 };

typedef struct {
  uint32_t last;     /* absolute tick of the compare currently programmed */
  uint32_t target;   /* absolute tick of the next real edge */
  uint8_t phase;
  uint8_t hopping;   /* the programmed compare is a hop, not an edge */
  uint8_t fall_near; /* the falling edge is within one counter lap of the rise */
  uint16_t fall_ocr; /* then its compare value, precomputed */
} channel;

/* Only touched by the compare ISRs (which do not nest) and by
 * pulse_start() with interrupts off, so not volatile: the ISRs keep it in
 * registers, which matters for 20 us pulses (320 cycles from a rising
 * edge, for both channels' ISRs, to have programmed the falling edge). */
static channel ch[TRIG_CHANNELS];
static trig_timing active, pending;
static volatile uint8_t pending_valid, stop_requested, running;
static uint32_t base;     /* absolute tick at which the current period began */
static uint32_t frac_acc; /* Bresenham accumulator for the period fraction */
static volatile uint32_t count;
static volatile uint16_t laps;
static volatile uint32_t lap_ms;
static volatile uint16_t lap_us;

static inline __attribute__((always_inline)) void set_com(uint8_t c, uint8_t mode) {
  if (c == TRIG_CH_A)
    TCCR1A = (uint8_t)((TCCR1A & ~((1 << COM1A1) | (1 << COM1A0))) | (mode << COM1A0));
  else
    TCCR1A = (uint8_t)((TCCR1A & ~((1 << COM1B1) | (1 << COM1B0))) | (mode << COM1B0));
}

/* Programs channel c's next compare towards its target. The compare mode is
 * written before the compare value (simavr re-evaluates the pin when OCR1x
 * is written, and real hardware does not care about the order). */
static void arm(uint8_t c) {
  channel *k = &ch[c];
  uint32_t left = k->target - k->last;
  if (left > 0xFFFFU) {
    left = HOP;
    k->hopping = 1;
    set_com(c, COM_OFF);
  } else {
    k->hopping = 0;
    set_com(c, k->phase == WAIT_RISE ? COM_SET : COM_CLEAR);
  }
  k->last += left;
  if (c == TRIG_CH_A)
    OCR1A = (uint16_t)k->last;
  else
    OCR1B = (uint16_t)k->last;
}

static void arm_rises(void) {
  for (uint8_t c = 0; c < TRIG_CHANNELS; ++c) {
    ch[c].target = base + active.delay_ticks[c];
    ch[c].phase = WAIT_RISE;
    ch[c].fall_near = active.width_ticks <= 0xFFFFU;
    ch[c].fall_ocr = (uint16_t)(ch[c].target + active.width_ticks);
    arm(c);
  }
}

/* Both pulses of the period are over: the only place where timing changes
 * and stops take effect, so no pulse is ever cut or stretched. */
static uint32_t now_ticks(void);

/* Both pulses of the period are over: the only place where timing changes
 * and stops take effect, so no pulse is ever cut or stretched. New timing
 * already sets the distance to the next rising edge when that edge is
 * still at least the guard time ahead (a shorter period whose start would
 * already be past keeps the old distance once). */
static void period_end(void) {
  if (stop_requested) {
    stop_requested = 0;
    running = 0;
    TIMSK1 &= (uint8_t)~((1 << OCIE1A) | (1 << OCIE1B));
    set_com(TRIG_CH_A, COM_OFF);
    set_com(TRIG_CH_B, COM_OFF);
    return;
  }
  uint32_t next = base + active.period_ticks;
  frac_acc += active.period_frac;
  if (frac_acc >= active.rate_mhz) {
    frac_acc -= active.rate_mhz;
    ++next;
  }
  if (pending_valid) {
    const uint32_t sooner = base + pending.period_ticks;
    if ((int32_t)(sooner - now_ticks()) >= (int32_t)(TRIG_GUARD_US * TRIG_TICKS_PER_US)) next = sooner;
    active = pending;
    pending_valid = 0;
    frac_acc = 0;
  }
  base = next;
  arm_rises();
}

static inline __attribute__((always_inline)) void on_compare(uint8_t c) {
  channel *k = &ch[c];
  if (k->phase == WAIT_RISE && !k->hopping) {
    if (c == TRIG_CH_A) SYNC_PORT |= (1 << SYNC_BIT);
    k->phase = WAIT_FALL;
    if (k->fall_near) {
      /* The time-critical path: program the falling edge first, 16-bit. */
      const uint16_t fall = k->fall_ocr;
      set_com(c, COM_CLEAR);
      if (c == TRIG_CH_A) {
        OCR1A = fall;
        /* Safety net for real hardware if the ISR was held off past the
         * falling edge: force the "clear" action now (a slightly long
         * pulse instead of one a whole counter lap long). */
        if ((int16_t)(TCNT1 - fall) >= 0) TCCR1C = (1 << FOC1A);
      } else {
        OCR1B = fall;
        if ((int16_t)(TCNT1 - fall) >= 0) TCCR1C = (1 << FOC1B);
      }
      k->target += active.width_ticks;
      k->last = k->target;
    } else {
      k->target += active.width_ticks;
      arm(c);
    }
    if (c == TRIG_CH_A) ++count;
    return;
  }
  if (k->hopping) {
    arm(c);
    return;
  }
  if (c == TRIG_CH_A) SYNC_PORT &= (uint8_t)~(1 << SYNC_BIT);
  k->phase = DONE;
  set_com(c, COM_OFF);
  if (ch[1 - c].phase == DONE) period_end();
}

/* Each ISR also serves the other channel when its match is already
 * pending (both cameras' edges on the same tick), so the second falling
 * edge is programmed without a second interrupt entry and exit. */
ISR(TIMER1_COMPA_vect) {
  on_compare(TRIG_CH_A);
  if (TIFR1 & (1 << OCF1B)) {
    TIFR1 = (1 << OCF1B);
    on_compare(TRIG_CH_B);
  }
}

ISR(TIMER1_COMPB_vect) {
  on_compare(TRIG_CH_B);
  if (TIFR1 & (1 << OCF1A)) {
    TIFR1 = (1 << OCF1A);
    on_compare(TRIG_CH_A);
  }
}

/* One lap = 65536 ticks = 32.768 ms. */
ISR(TIMER1_OVF_vect) {
  ++laps;
  lap_ms += 32;
  lap_us += 768;
  if (lap_us >= 1000) {
    lap_us -= 1000;
    ++lap_ms;
  }
}

/* Absolute tick now; interrupts must be off. */
static uint32_t now_ticks(void) {
  const uint16_t t = TCNT1;
  uint16_t l = laps;
  if ((TIFR1 & (1 << TOV1)) && t < 0x8000U) ++l;
  return ((uint32_t)l << 16) | t;
}

void pulse_init(void) {
  DDRB |= (1 << PB1) | (1 << PB2);
  SYNC_DDR |= (1 << SYNC_BIT);
  TCCR1A = 0;
  TCCR1B = (1 << CS11); /* normal mode, clk/8 */
  TIMSK1 = (1 << TOIE1);
  trig_settings s;
  trig_default_settings(&s);
  trig_compute(&s, &active);
}

void pulse_configure(const trig_timing *t) {
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    if (running) {
      pending = *t;
      pending_valid = 1;
    } else {
      active = *t;
    }
  }
}

void pulse_start(void) {
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    stop_requested = 0;
    if (!running) {
      if (pending_valid) {
        active = pending;
        pending_valid = 0;
      }
      const uint32_t now = now_ticks();
      base = now + START_LEAD_TICKS;
      frac_acc = 0;
      for (uint8_t c = 0; c < TRIG_CHANNELS; ++c) ch[c].last = now;
      arm_rises();
      TIFR1 = (1 << OCF1A) | (1 << OCF1B); /* stale matches from the stopped time */
      TIMSK1 |= (1 << OCIE1A) | (1 << OCIE1B);
      running = 1;
    }
  }
}

void pulse_stop(void) {
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    if (running) stop_requested = 1;
  }
}

uint32_t pulse_count(void) {
  uint32_t n;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { n = count; }
  return n;
}

uint32_t pulse_uptime_ms(void) {
  uint32_t ms;
  uint16_t us, t;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    ms = lap_ms;
    us = lap_us;
    t = TCNT1;
    if ((TIFR1 & (1 << TOV1)) && t < 0x8000U) ms += 33;
  }
  return ms + (us + t / TRIG_TICKS_PER_US) / 1000U;
}
