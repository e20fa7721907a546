#include "trig_crc16.h"

/* Bitwise, exactly the C equivalent avr-libc documents for _crc16_update. */
uint16_t trig_crc16_update(uint16_t crc, uint8_t byte) {
  crc ^= byte;
  for (int i = 0; i < 8; ++i) crc = (crc & 1) ? (uint16_t)((crc >> 1) ^ 0xA001) : (uint16_t)(crc >> 1);
  return crc;
}
