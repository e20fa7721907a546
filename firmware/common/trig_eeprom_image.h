/* The settings as stored in EEPROM: a fixed little-endian layout with a
 * magic, a layout version and a CRC-16, so a blank (0xFF), torn or foreign
 * EEPROM is recognised and the defaults are used instead.
 *
 *   0  'S'          magic
 *   1  1            layout version
 *   2  rate_mhz     u32
 *   6  width_us     u32
 *  10  delay_a_us   u32
 *  14  delay_b_us   u32
 *  18  running      u8 (state at power-on)
 *  19  crc16        u16 over bytes 0..18, init 0xFFFF (trig_crc16.h) */
#ifndef TRIG_EEPROM_IMAGE_H
#define TRIG_EEPROM_IMAGE_H

#include <stdint.h>

#include "trig_protocol.h"

#define TRIG_EEPROM_MAGIC 0x53
#define TRIG_EEPROM_LAYOUT 1
#define TRIG_EEPROM_SIZE 21

void trig_eeprom_encode(const trig_state *st, uint8_t image[TRIG_EEPROM_SIZE]);

/* 1 and fills `st` when the image is intact and its settings valid;
 * 0 (st untouched) otherwise. */
int trig_eeprom_decode(const uint8_t image[TRIG_EEPROM_SIZE], trig_state *st);

#endif
