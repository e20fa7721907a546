#include "trig_eeprom_image.h"

#include "trig_crc16.h"

#define CRC_INIT 0xFFFF
#define PAYLOAD (TRIG_EEPROM_SIZE - 2)

static void put_le32(uint8_t *p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t get_u32(const uint8_t *p) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

void trig_eeprom_encode(const trig_state *st, uint8_t image[TRIG_EEPROM_SIZE]) {
  image[0] = TRIG_EEPROM_MAGIC;
  image[1] = TRIG_EEPROM_LAYOUT;
  put_le32(image + 2, st->settings.rate_mhz);
  put_le32(image + 6, st->settings.width_us);
  put_le32(image + 10, st->settings.delay_us[TRIG_CH_A]);
  put_le32(image + 14, st->settings.delay_us[TRIG_CH_B]);
  image[18] = st->running ? 1 : 0;
  const uint16_t crc = trig_crc16(CRC_INIT, image, PAYLOAD);
  image[19] = (uint8_t)crc;
  image[20] = (uint8_t)(crc >> 8);
}

int trig_eeprom_decode(const uint8_t image[TRIG_EEPROM_SIZE], trig_state *st) {
  const uint16_t crc = (uint16_t)(image[19] | (image[20] << 8));
  if (image[0] != TRIG_EEPROM_MAGIC || image[1] != TRIG_EEPROM_LAYOUT) return 0;
  if (trig_crc16(CRC_INIT, image, PAYLOAD) != crc) return 0;
  if (image[18] > 1) return 0;
  trig_state decoded;
  decoded.settings.rate_mhz = get_u32(image + 2);
  decoded.settings.width_us = get_u32(image + 6);
  decoded.settings.delay_us[TRIG_CH_A] = get_u32(image + 10);
  decoded.settings.delay_us[TRIG_CH_B] = get_u32(image + 14);
  decoded.running = image[18];
  if (trig_validate(&decoded.settings)) return 0;
  *st = decoded;
  return 1;
}
