/* The pulse generator: Timer1 output-compare hardware makes every camera
 * edge (OC1A = camera A on PB1/D9, OC1B = camera B on PB2/D10); the sync
 * line to the Linux GPIO (PD7/D7) follows camera A from the compare ISR. */
#ifndef PULSE_H
#define PULSE_H

#include <stdint.h>

#include "trig_timing.h"

void pulse_init(void); /* Timer1 free-running at F_CPU/8; pins low; stopped */

/* New timing; while running it takes effect at the next period boundary
 * (after both cameras' pulses of the current period have ended). */
void pulse_configure(const trig_timing *t);

void pulse_start(void); /* first pulse 100 us later; no-op when running */
void pulse_stop(void);  /* after the current period, never cutting a pulse */

uint32_t pulse_count(void);     /* camera A pulses since power-on */
uint32_t pulse_uptime_ms(void); /* from Timer1 laps, since power-on */

#endif
