/* USART0 at 115200 8N1 with interrupt-driven ring buffers both ways. */
#ifndef UART_H
#define UART_H

#include <stdint.h>

void uart_init(void);
int uart_getc(void);          /* next received byte, -1 when none */
uint8_t uart_overrun(void);   /* bytes dropped since the last call (ring full or hardware overrun) */
void uart_putc(char c);       /* waits while the transmit ring is full */
void uart_puts(const char *s);

#endif
