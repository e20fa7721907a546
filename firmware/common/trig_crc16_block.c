#include "trig_crc16.h"

uint16_t trig_crc16(uint16_t init, const uint8_t *data, size_t len) {
  uint16_t crc = init;
  for (size_t i = 0; i < len; ++i) crc = trig_crc16_update(crc, data[i]);
  return crc;
}
