// The trigger controller's firmware parser (firmware/common, compiled for
// the host from the same C files avr-gcc builds): the input is the byte
// stream on its UART, assembled into lines and handled as the firmware's
// main loop does. Checked after every line: exactly one reply, "OK..." or
// "ERR <reason>" within TRIG_REPLY_MAX; a rejected line changes nothing;
// the settings stay valid; an accepted number is the number the line says
// (a decimal reference parse here); and at the end the host's STATUS
// parser reads the firmware's STATUS reply back to the same settings.
#include <cctype>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

extern "C" {
#include "trig_protocol.h"
}

#include "fuzz_support.hpp"
#include "spinewatch/sync/trigger_controller.hpp"

namespace {

std::vector<std::string> tokens(const char* line) {
  std::vector<std::string> out;
  std::string current;
  for (const char* p = line;; ++p) {
    if (*p == ' ' || *p == '\t' || *p == '\0') {
      if (!current.empty()) out.push_back(current);
      current.clear();
      if (*p == '\0') break;
    } else {
      current += *p;
    }
  }
  return out;
}

// The reference: digits, optionally '.' and up to `frac_digits` digits,
// as an integer scaled by 10^frac_digits (64-bit: no 12-digit figure overflows).
std::optional<std::uint64_t> reference_fixed(const std::string& text, int frac_digits) {
  std::uint64_t v = 0;
  int frac = -1, digits = 0;
  for (char c : text) {
    if (c == '.' && frac < 0 && frac_digits > 0) {
      frac = 0;
      continue;
    }
    if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
    if (++digits > 18) return std::nullopt;
    v = v * 10 + static_cast<std::uint64_t>(c - '0');
    if (frac >= 0) ++frac;
  }
  if (frac < 0) frac = 0;
  if (frac > frac_digits) return std::nullopt;
  for (; frac < frac_digits; ++frac) v *= 10;
  return v;
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

void check_numbers(const std::vector<std::string>& t, const trig_settings& s, const std::string& line) {
  const std::string cmd = upper(t[0]);
  auto expect = [&](const std::string& text, int frac, std::uint32_t got) {
    const auto want = reference_fixed(text, frac);
    FUZZ_CHECK(want && *want == got, line + " was taken as " + std::to_string(got));
  };
  if (cmd == "RATE") expect(t[1], 3, s.rate_mhz);
  if (cmd == "WIDTH") expect(t[1], 0, s.width_us);
  if (cmd == "DELAY") expect(t[2], 0, s.delay_us[upper(t[1]) == "A" ? TRIG_CH_A : TRIG_CH_B]);
  if (cmd == "CONFIG") {
    expect(t[1], 3, s.rate_mhz);
    expect(t[2], 0, s.width_us);
    expect(t[3], 0, s.delay_us[TRIG_CH_A]);
    expect(t[4], 0, s.delay_us[TRIG_CH_B]);
  }
}

bool same(const trig_state& a, const trig_state& b) {
  return a.running == b.running && a.settings.rate_mhz == b.settings.rate_mhz &&
         a.settings.width_us == b.settings.width_us && a.settings.delay_us[0] == b.settings.delay_us[0] &&
         a.settings.delay_us[1] == b.settings.delay_us[1];
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  trig_state st{};
  trig_default_settings(&st.settings);
  trig_linebuf lb;
  trig_linebuf_init(&lb);
  trig_live live{0, 0};
  char reply[TRIG_REPLY_MAX];

  for (std::size_t i = 0; i < size; ++i) {
    if (trig_linebuf_push(&lb, static_cast<char>(data[i])) != TRIG_LINE_READY) continue;
    live = {live.count + 7, live.uptime_ms + 33};
    const trig_state before = st;
    std::memset(reply, 0x55, sizeof reply);
    trig_handle_line(&st, lb.buf, &live, reply, sizeof reply);
    const std::size_t length = ::strnlen(reply, sizeof reply);
    FUZZ_CHECK(length < sizeof reply, "a reply without its NUL");
    const std::string text(reply, length);
    const std::string line(lb.buf);
    FUZZ_CHECK(text.rfind("OK", 0) == 0 || text.rfind("ERR ", 0) == 0, line + " -> " + text);
    FUZZ_CHECK(text.find('\n') == std::string::npos && text.find('\r') == std::string::npos, text);
    if (text.rfind("ERR ", 0) == 0)
      FUZZ_CHECK(same(before, st), line + " was rejected but changed the state");
    else
      check_numbers(tokens(lb.buf), st.settings, line);
    FUZZ_CHECK(trig_validate(&st.settings) == nullptr, line + " left invalid settings");
    FUZZ_CHECK(st.running == 0 || st.running == 1, line);
  }

  // The host reads the firmware's STATUS back to the same figures.
  trig_handle_line(&st, "STATUS", &live, reply, sizeof reply);
  auto status = spinewatch::sync::parse_trigger_status(reply);
  FUZZ_CHECK(status.ok(), reply);
  FUZZ_CHECK(std::llround(status->rate_hz * 1000) == st.settings.rate_mhz, reply);
  FUZZ_CHECK(status->width_us == static_cast<int>(st.settings.width_us), reply);
  FUZZ_CHECK(status->delay_a_us == static_cast<int>(st.settings.delay_us[TRIG_CH_A]), reply);
  FUZZ_CHECK(status->delay_b_us == static_cast<int>(st.settings.delay_us[TRIG_CH_B]), reply);
  FUZZ_CHECK(status->running == (st.running == 1), reply);
  FUZZ_CHECK(status->count == live.count && status->uptime_ms == live.uptime_ms, reply);
  return 0;
}
