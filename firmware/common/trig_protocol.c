#include "trig_protocol.h"

#include <string.h>

/* ---- line assembly ---- */

void trig_linebuf_init(trig_linebuf *lb) {
  lb->len = 0;
  lb->too_long = 0;
  lb->buf[0] = '\0';
}

trig_line_result trig_linebuf_push(trig_linebuf *lb, char c) {
  if (c == '\n') {
    uint8_t len = lb->len;
    const uint8_t overflowed = lb->too_long;
    lb->len = 0;
    lb->too_long = 0;
    if (len > 0 && lb->buf[len - 1] == '\r') --len; /* "\r\n" line ends */
    if (overflowed || len > TRIG_LINE_MAX) return TRIG_LINE_TOO_LONG;
    lb->buf[len] = '\0';
    return TRIG_LINE_READY;
  }
  /* One spare place keeps the '\r' of a full-length "\r\n" line. */
  if (lb->len < TRIG_LINE_MAX + 1)
    lb->buf[lb->len++] = c;
  else
    lb->too_long = 1;
  return TRIG_LINE_PENDING;
}

/* ---- reply writer: no printf, so no float or large libc code on the AVR ---- */

typedef struct {
  char *p;
  size_t left; /* room for characters, excluding the NUL */
} writer;

static void put_str(writer *w, const char *s) {
  while (*s && w->left) {
    *w->p++ = *s++;
    --w->left;
  }
  *w->p = '\0';
}

static void put_u32(writer *w, uint32_t v) {
  char digits[11];
  int n = 0;
  do {
    digits[n++] = (char)('0' + v % 10);
    v /= 10;
  } while (v);
  while (n && w->left) {
    *w->p++ = digits[--n];
    --w->left;
  }
  *w->p = '\0';
}

static void put_field(writer *w, const char *name, uint32_t v) {
  put_str(w, " ");
  put_str(w, name);
  put_str(w, "=");
  put_u32(w, v);
}

size_t trig_format_mhz(uint32_t mhz, char *out, size_t cap) {
  writer w = {out, cap - 1};
  uint32_t frac = mhz % 1000;
  put_u32(&w, mhz / 1000);
  put_str(&w, ".");
  put_str(&w, frac < 100 ? (frac < 10 ? "00" : "0") : "");
  put_u32(&w, frac);
  return (size_t)(w.p - out);
}

/* ---- tokens and numbers ---- */

static char upper(char c) { return (c >= 'a' && c <= 'z') ? (char)(c - 'a' + 'A') : c; }

/* Next space-separated token; returns its length, 0 at the end. */
static size_t next_token(const char **cursor, const char **token) {
  const char *s = *cursor;
  while (*s == ' ' || *s == '\t') ++s;
  *token = s;
  while (*s && *s != ' ' && *s != '\t') ++s;
  *cursor = s;
  return (size_t)(s - *token);
}

static int token_is(const char *token, size_t len, const char *word) {
  size_t i = 0;
  for (; i < len && word[i]; ++i)
    if (upper(token[i]) != word[i]) return 0;
  return i == len && word[i] == '\0';
}

/* v * 10 + the digit c, or 0 when that does not fit in 32 bits. */
static int push_digit(uint32_t *v, char c) {
  const uint32_t d = (uint32_t)(c - '0');
  if (*v > (UINT32_MAX - d) / 10) return 0;
  *v = *v * 10 + d;
  return 1;
}

/* Unsigned decimal with up to `frac_digits` fraction digits, scaled by
 * 10^frac_digits; at most 9 integer digits, and a figure that does not
 * fit in 32 bits once scaled is refused, not wrapped ("RATE 4294968.296"
 * was once taken as 1 Hz; tests/fuzz/trigger_firmware_fuzz.cpp checks every
 * accepted figure against a reference parse). */
static int parse_fixed(const char *s, size_t len, uint8_t frac_digits, uint32_t *out) {
  uint32_t v = 0;
  size_t i = 0;
  uint8_t int_digits = 0, frac_seen = 0;
  for (; i < len && s[i] >= '0' && s[i] <= '9'; ++i) {
    if (++int_digits > 9) return 0;
    v = v * 10 + (uint32_t)(s[i] - '0');
  }
  if (int_digits == 0) return 0;
  if (i < len && s[i] == '.' && frac_digits > 0) {
    ++i;
    for (; i < len && s[i] >= '0' && s[i] <= '9'; ++i) {
      if (++frac_seen > frac_digits) return 0;
      if (!push_digit(&v, s[i])) return 0;
    }
    if (frac_seen == 0) return 0;
  }
  if (i != len) return 0;
  for (; frac_seen < frac_digits; ++frac_seen) {
    if (v > 429496729UL) return 0;
    v *= 10;
  }
  *out = v;
  return 1;
}

/* ---- commands ---- */

static uint8_t reply_err(writer *w, const char *reason) {
  put_str(w, "ERR ");
  put_str(w, reason);
  return TRIG_ACT_NONE;
}

static uint8_t reply_ok(writer *w, uint8_t actions) {
  put_str(w, "OK");
  return actions;
}

/* Replaces the settings when the candidate is valid. */
static uint8_t try_settings(trig_state *st, const trig_settings *candidate, writer *w) {
  const char *problem = trig_validate(candidate);
  if (problem) return reply_err(w, problem);
  st->settings = *candidate;
  return reply_ok(w, TRIG_ACT_APPLY);
}

static void put_status(writer *w, const trig_state *st, const trig_live *live) {
  char rate[16];
  trig_format_mhz(st->settings.rate_mhz, rate, sizeof rate);
  put_str(w, "OK rate=");
  put_str(w, rate);
  put_field(w, "width", st->settings.width_us);
  put_field(w, "delay_a", st->settings.delay_us[TRIG_CH_A]);
  put_field(w, "delay_b", st->settings.delay_us[TRIG_CH_B]);
  put_field(w, "running", st->running);
  put_field(w, "count", live->count);
  put_field(w, "uptime_ms", live->uptime_ms);
}

uint8_t trig_handle_line(trig_state *st, const char *line, const trig_live *live, char *reply, size_t cap) {
  writer w = {reply, cap - 1};
  reply[0] = '\0';
  const char *cursor = line;
  const char *cmd, *arg[4];
  size_t arg_len[4];
  const size_t cmd_len = next_token(&cursor, &cmd);
  size_t argc = 0;
  for (; argc < 4; ++argc)
    if ((arg_len[argc] = next_token(&cursor, &arg[argc])) == 0) break;
  const char *extra;
  if (argc == 4 && next_token(&cursor, &extra) != 0) return reply_err(&w, "too many arguments");

  if (cmd_len == 0) return reply_err(&w, "empty line");

  trig_settings next = st->settings;
  if (token_is(cmd, cmd_len, "RATE")) {
    if (argc != 1) return reply_err(&w, "usage: RATE <hz>");
    if (!parse_fixed(arg[0], arg_len[0], 3, &next.rate_mhz)) return reply_err(&w, "bad number");
    return try_settings(st, &next, &w);
  }
  if (token_is(cmd, cmd_len, "WIDTH")) {
    if (argc != 1) return reply_err(&w, "usage: WIDTH <us>");
    if (!parse_fixed(arg[0], arg_len[0], 0, &next.width_us)) return reply_err(&w, "bad number");
    return try_settings(st, &next, &w);
  }
  if (token_is(cmd, cmd_len, "DELAY")) {
    if (argc != 2) return reply_err(&w, "usage: DELAY <A|B> <us>");
    int ch = token_is(arg[0], arg_len[0], "A") ? TRIG_CH_A : token_is(arg[0], arg_len[0], "B") ? TRIG_CH_B : -1;
    if (ch < 0) return reply_err(&w, "channel must be A or B");
    if (!parse_fixed(arg[1], arg_len[1], 0, &next.delay_us[ch])) return reply_err(&w, "bad number");
    return try_settings(st, &next, &w);
  }
  if (token_is(cmd, cmd_len, "CONFIG")) {
    if (argc != 4) return reply_err(&w, "usage: CONFIG <hz> <width_us> <delay_a_us> <delay_b_us>");
    if (!parse_fixed(arg[0], arg_len[0], 3, &next.rate_mhz) || !parse_fixed(arg[1], arg_len[1], 0, &next.width_us) ||
        !parse_fixed(arg[2], arg_len[2], 0, &next.delay_us[TRIG_CH_A]) ||
        !parse_fixed(arg[3], arg_len[3], 0, &next.delay_us[TRIG_CH_B]))
      return reply_err(&w, "bad number");
    return try_settings(st, &next, &w);
  }
  static const char *const no_argument[] = {"START", "STOP", "STATUS", "VERSION", "SAVE", "DEFAULTS"};
  uint8_t known = 0;
  for (uint8_t i = 0; i < sizeof no_argument / sizeof no_argument[0]; ++i) known |= (uint8_t)token_is(cmd, cmd_len, no_argument[i]);
  if (!known) return reply_err(&w, "unknown command");
  if (argc != 0) return reply_err(&w, "unexpected argument");
  if (token_is(cmd, cmd_len, "START")) {
    st->running = 1;
    return reply_ok(&w, TRIG_ACT_START);
  }
  if (token_is(cmd, cmd_len, "STOP")) {
    st->running = 0;
    return reply_ok(&w, TRIG_ACT_STOP);
  }
  if (token_is(cmd, cmd_len, "STATUS")) {
    put_status(&w, st, live);
    return TRIG_ACT_NONE;
  }
  if (token_is(cmd, cmd_len, "VERSION")) {
    put_str(&w, "OK spinewatch-trigger " TRIG_FIRMWARE_VERSION " proto=");
    put_u32(&w, TRIG_PROTOCOL_VERSION);
    return TRIG_ACT_NONE;
  }
  if (token_is(cmd, cmd_len, "SAVE")) return reply_ok(&w, TRIG_ACT_SAVE);
  if (token_is(cmd, cmd_len, "DEFAULTS")) {
    trig_default_settings(&st->settings);
    return reply_ok(&w, TRIG_ACT_APPLY);
  }
  return reply_err(&w, "unknown command");
}
