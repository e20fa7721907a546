/* Settings in EEPROM (layout: common/trig_eeprom_image.h). */
#ifndef STORE_H
#define STORE_H

#include "trig_protocol.h"

/* 1 when the stored image was intact; otherwise `st` gets the defaults
 * (30 Hz, 1000 us, no delays, running) and 0 is returned. */
uint8_t store_load(trig_state *st);

/* 1 when the image read back equals what was written. */
uint8_t store_save(const trig_state *st);

#endif
