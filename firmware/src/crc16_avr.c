/* The device uses avr-libc's optimised CRC routine; host builds use the
 * portable one in common/trig_crc16.c (same polynomial, tested equal). */
#include <util/crc16.h>

#include "trig_crc16.h"

uint16_t trig_crc16_update(uint16_t crc, uint8_t byte) { return _crc16_update(crc, byte); }
