/* spinewatch trigger controller: ATmega328P at 16 MHz (Arduino Nano class).
 * Reads protocol lines from the UART, hands settings to the pulse
 * generator and answers every line with exactly one OK/ERR line. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>

#include "pulse.h"
#include "store.h"
#include "trig_protocol.h"
#include "uart.h"

static void apply(const trig_state *st) {
  trig_timing t;
  trig_compute(&st->settings, &t);
  pulse_configure(&t);
}

/* Sleeps until any interrupt; the check and the sleep are atomic so a byte
 * arriving in between is not left waiting for the next interrupt. */
static int wait_byte(void) {
  for (;;) {
    cli();
    const int c = uart_getc();
    if (c >= 0) {
      sei();
      return c;
    }
    sleep_enable();
    sei();
    sleep_cpu();
    sleep_disable();
  }
}

int main(void) {
  trig_state st;
  trig_linebuf line;
  char reply[TRIG_REPLY_MAX];

  store_load(&st);
  pulse_init();
  uart_init();
  set_sleep_mode(SLEEP_MODE_IDLE);
  apply(&st);
  sei();
  if (st.running) pulse_start();

  trig_linebuf_init(&line);
  uint8_t garbled = 0; /* bytes of the current line were lost */
  for (;;) {
    const char c = (char)wait_byte();
    if (uart_overrun()) garbled = 1;
    const trig_line_result r = trig_linebuf_push(&line, c);
    if (r == TRIG_LINE_PENDING) continue;
    if (garbled) {
      uart_puts("ERR input overrun");
    } else if (r == TRIG_LINE_TOO_LONG) {
      uart_puts("ERR line too long");
    } else {
      const trig_live live = {pulse_count(), pulse_uptime_ms()};
      const uint8_t act = trig_handle_line(&st, line.buf, &live, reply, sizeof reply);
      if (act & TRIG_ACT_APPLY) apply(&st);
      if (act & TRIG_ACT_START) pulse_start();
      if (act & TRIG_ACT_STOP) pulse_stop();
      if ((act & TRIG_ACT_SAVE) && !store_save(&st)) uart_puts("ERR eeprom write failed");
      else uart_puts(reply);
    }
    garbled = 0;
    uart_puts("\n");
  }
}
