/* CRC-16 as computed by avr-libc's _crc16_update() (<util/crc16.h>):
 * polynomial 0x8005 reflected (0xA001), no final XOR. The firmware links
 * firmware/src/crc16_avr.c (the avr-libc routine), host builds link
 * trig_crc16.c; the unit tests pin this one to the published check values
 * and the simavr test boots the device from an image made with it. */
#ifndef TRIG_CRC16_H
#define TRIG_CRC16_H

#include <stddef.h>
#include <stdint.h>

uint16_t trig_crc16_update(uint16_t crc, uint8_t byte);
uint16_t trig_crc16(uint16_t init, const uint8_t *data, size_t len);

#endif
