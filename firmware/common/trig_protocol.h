/* The line protocol of the trigger controller (docs/trigger-protocol.md).
 *
 * Pure C99, shared by the firmware and the host tests (including the fake
 * controller the host client is tested against), so the device and the
 * client agree on every reply by construction. */
#ifndef TRIG_PROTOCOL_H
#define TRIG_PROTOCOL_H

#include <stddef.h>
#include <stdint.h>

#include "trig_timing.h"

#define TRIG_FIRMWARE_VERSION "1.0.0"
#define TRIG_PROTOCOL_VERSION 1
#define TRIG_LINE_MAX 48   /* characters, without the line end */
#define TRIG_REPLY_MAX 128 /* bytes including the NUL; STATUS is the longest */

/* Assembles input bytes into lines. A line longer than TRIG_LINE_MAX is
 * swallowed up to its newline and reported once, so the stream
 * resynchronises on the next line. */
typedef struct {
  char buf[TRIG_LINE_MAX + 2];
  uint8_t len;
  uint8_t too_long;
} trig_linebuf;

typedef enum {
  TRIG_LINE_PENDING = 0, /* no complete line yet */
  TRIG_LINE_READY,       /* buf holds the line, NUL-terminated, without "\r\n" */
  TRIG_LINE_TOO_LONG     /* a line ended that was longer than TRIG_LINE_MAX */
} trig_line_result;

void trig_linebuf_init(trig_linebuf *lb);
trig_line_result trig_linebuf_push(trig_linebuf *lb, char c);

/* What the controller is set to; `running` is the requested state (the
 * pulse generator stops at the end of the current period). */
typedef struct {
  trig_settings settings;
  uint8_t running;
} trig_state;

/* Figures only the device knows, sampled just before a line is handled. */
typedef struct {
  uint32_t count;     /* camera A pulses since power-on */
  uint32_t uptime_ms; /* since power-on */
} trig_live;

/* Actions for the caller after trig_handle_line (bit mask). */
enum {
  TRIG_ACT_NONE = 0,
  TRIG_ACT_APPLY = 1, /* settings changed: hand them to the pulse generator */
  TRIG_ACT_START = 2,
  TRIG_ACT_STOP = 4,
  TRIG_ACT_SAVE = 8 /* write settings + running to EEPROM; on failure replace the reply */
};

/* Handles one line; always writes exactly one reply ("OK ..." or
 * "ERR <reason>", without the line end) into reply[cap]. A rejected line
 * leaves `st` untouched. */
uint8_t trig_handle_line(trig_state *st, const char *line, const trig_live *live, char *reply, size_t cap);

/* "30.000" for 30000 milli-hertz; returns the length written (cap >= 16). */
size_t trig_format_mhz(uint32_t mhz, char *out, size_t cap);

#endif
