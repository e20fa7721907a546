#include "store.h"

#include <avr/eeprom.h>
#include <string.h>

#include "trig_eeprom_image.h"

#define STORE_ADDRESS ((void *)0)

uint8_t store_load(trig_state *st) {
  uint8_t image[TRIG_EEPROM_SIZE];
  eeprom_read_block(image, STORE_ADDRESS, sizeof image);
  if (trig_eeprom_decode(image, st)) return 1;
  trig_default_settings(&st->settings);
  st->running = 1; /* a fresh box triggers on its own, host or not */
  return 0;
}

uint8_t store_save(const trig_state *st) {
  uint8_t image[TRIG_EEPROM_SIZE], check[TRIG_EEPROM_SIZE];
  trig_eeprom_encode(st, image);
  eeprom_update_block(image, STORE_ADDRESS, sizeof image);
  eeprom_read_block(check, STORE_ADDRESS, sizeof check);
  return memcmp(image, check, sizeof image) == 0;
}
