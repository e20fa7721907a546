#include "uart.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>

/* Powers of two, so the indices wrap with a mask. */
#define RX_SIZE 64
#define TX_SIZE 128

static volatile uint8_t rx_buf[RX_SIZE];
static volatile uint8_t rx_head, rx_tail;
static volatile uint8_t rx_dropped;
static volatile uint8_t tx_buf[TX_SIZE];
static volatile uint8_t tx_head, tx_tail;

void uart_init(void) {
  /* 16 MHz, U2X: UBRR 16 -> 117647 baud (+2.1 %), the usual Arduino setting. */
  UCSR0A = (1 << U2X0);
  UBRR0 = 16;
  UCSR0C = (1 << UCSZ01) | (1 << UCSZ00);
  UCSR0B = (1 << RXEN0) | (1 << TXEN0) | (1 << RXCIE0);
}

ISR(USART_RX_vect) {
  const uint8_t status = UCSR0A;
  const uint8_t c = UDR0;
  if (status & ((1 << DOR0) | (1 << FE0))) ++rx_dropped;
  const uint8_t next = (uint8_t)((rx_head + 1) & (RX_SIZE - 1));
  if (next == rx_tail) {
    ++rx_dropped;
    return;
  }
  rx_buf[rx_head] = c;
  rx_head = next;
}

ISR(USART_UDRE_vect) {
  if (tx_head == tx_tail) {
    UCSR0B &= (uint8_t)~(1 << UDRIE0);
    return;
  }
  UDR0 = tx_buf[tx_tail];
  tx_tail = (uint8_t)((tx_tail + 1) & (TX_SIZE - 1));
}

int uart_getc(void) {
  if (rx_head == rx_tail) return -1;
  const uint8_t c = rx_buf[rx_tail];
  rx_tail = (uint8_t)((rx_tail + 1) & (RX_SIZE - 1));
  return c;
}

uint8_t uart_overrun(void) {
  uint8_t n;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    n = rx_dropped;
    rx_dropped = 0;
  }
  return n;
}

void uart_putc(char c) {
  const uint8_t next = (uint8_t)((tx_head + 1) & (TX_SIZE - 1));
  while (next == tx_tail) {
  }
  tx_buf[tx_head] = (uint8_t)c;
  tx_head = next;
  UCSR0B |= (1 << UDRIE0);
}

void uart_puts(const char *s) {
  while (*s) uart_putc(*s++);
}
