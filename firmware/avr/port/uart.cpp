#include "port/uart.h"

#include <Arduino.h>
#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>

// Timer0 overflows since power-on: Arduino's wiring.c, or the image's own
// clock (sketches/mb2co-gateway/gateway_main.cpp).
extern volatile unsigned long timer0_overflow_count;

namespace mb2co {
namespace avr {
namespace {

static_assert((kUartRxRing & (kUartRxRing - 1)) == 0 && kUartRxRing <= 16,
              "receive ring: a power of two, one error bit each in a uint16_t");
static_assert((kUartTxRing & (kUartTxRing - 1)) == 0, "transmit ring: a power of two");

// Receive ring, written by the ISR at rx_head, read by the main loop at
// rx_tail; empty when equal (one slot stays free). Stamps are micros() / 4.
uint8_t rx_byte[kUartRxRing];
uint16_t rx_stamp[kUartRxRing];
volatile uint16_t rx_error_bits;  ///< bit i: slot i is an invalid character
volatile uint8_t rx_head;
volatile uint8_t rx_tail;
bool rx_lost_pending;  ///< ISR only: a character was dropped, flag the next one

uint8_t tx_buf[kUartTxRing];
volatile uint8_t tx_head;
volatile uint8_t tx_tail;

volatile UartCounters counters;

// micros() / 4 in 16 bits, as the receive interrupt stamps a character
// (interrupts off): Timer0 ticks every 4 us and its overflow count is the
// rest of micros() (the core's wiring.c, or the image's own clock with the
// same variable). Inline: a call from an interrupt saves every
// call-clobbered register.
inline uint16_t stamp4_in_isr() {
  // Its low byte is all a 16-bit stamp keeps (little-endian: the first).
  uint8_t overflows = *reinterpret_cast<volatile uint8_t*>(&timer0_overflow_count);
  const uint8_t ticks = TCNT0;
  // An overflow not yet counted: the counter wrapped (as micros() decides).
  if ((TIFR0 & _BV(TOV0)) && ticks < 255) ++overflows;
  return static_cast<uint16_t>((static_cast<uint16_t>(overflows) << 8) | ticks);
}

bool sink_write(void*, const uint8_t* data, uint16_t length) {
  return uart_write(data, length);
}

}  // namespace

void uart_begin(uint32_t baud, modbus::Parity parity) {
  // Double speed (U2X): 115200 baud is 117647 (+2.1 %) instead of 111111 (-3.5 %).
  const uint16_t ubrr = static_cast<uint16_t>((F_CPU / 4ul / baud - 1ul) / 2ul);
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    UCSR0B = 0;
    UBRR0H = static_cast<uint8_t>(ubrr >> 8);
    UBRR0L = static_cast<uint8_t>(ubrr);
    UCSR0A = _BV(U2X0);
    const uint8_t parity_bits = parity == modbus::Parity::kEven  ? _BV(UPM01)
                                : parity == modbus::Parity::kOdd ? (_BV(UPM01) | _BV(UPM00))
                                                                 : 0;
    UCSR0C = static_cast<uint8_t>(parity_bits | _BV(UCSZ01) | _BV(UCSZ00));  // 8 data, 1 stop
    rx_head = rx_tail = 0;
    rx_error_bits = 0;
    rx_lost_pending = false;
    tx_head = tx_tail = 0;
    counters.rx_lost = 0;
    counters.rx_errors = 0;
    UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);
  }
}

bool uart_read(UartChar& out) {
  uint16_t stamp4;
  uint32_t now_us;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    const uint8_t tail = rx_tail;
    if (tail == rx_head) return false;
    out.byte = rx_byte[tail];
    out.error = (rx_error_bits & (1u << tail)) != 0;
    stamp4 = rx_stamp[tail];
    rx_tail = static_cast<uint8_t>((tail + 1u) & (kUartRxRing - 1u));
    // Read after the character was stored: its age below is never negative.
    now_us = micros();
  }
  const uint16_t age4 = static_cast<uint16_t>(static_cast<uint16_t>(now_us >> 2) - stamp4);
  out.stamp_us = (now_us & ~3ul) - 4ul * age4;
  return true;
}

bool uart_write(const uint8_t* data, uint16_t length) {
  for (uint16_t i = 0; i < length; ++i) {
    const uint8_t head = tx_head;
    const uint8_t next = static_cast<uint8_t>((head + 1u) & (kUartTxRing - 1u));
    while (next == tx_tail) {
    }  // full: the UDRE interrupt makes room (interrupts are on in the main loop)
    tx_buf[head] = data[i];
    tx_head = next;
    UCSR0B |= _BV(UDRIE0);
  }
  return true;
}

modbus::ByteSink uart_sink() {
  return modbus::ByteSink{&sink_write, nullptr};
}

UartCounters uart_counters() {
  UartCounters c;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    c.rx_lost = counters.rx_lost;
    c.rx_errors = counters.rx_errors;
  }
  return c;
}

}  // namespace avr
}  // namespace mb2co

using namespace mb2co::avr;

ISR(USART_RX_vect) {
  const uint8_t status = UCSR0A;  // error flags belong to the character in UDR0
  const uint8_t byte = UDR0;
  const uint16_t stamp4 = stamp4_in_isr();
  bool error = rx_lost_pending;
  if (status & _BV(DOR0)) {  // the hardware dropped characters before this one
    ++counters.rx_lost;
    error = true;
  }
  if (status & (_BV(FE0) | _BV(UPE0))) {
    ++counters.rx_errors;
    error = true;
  }
  const uint8_t head = rx_head;
  const uint8_t next = static_cast<uint8_t>((head + 1u) & (kUartRxRing - 1u));
  if (next == rx_tail) {  // ring full: drop, and mark the next stored character
    ++counters.rx_lost;
    rx_lost_pending = true;
    return;
  }
  rx_byte[head] = byte;
  rx_stamp[head] = stamp4;
  const uint16_t bit = static_cast<uint16_t>(1u << head);
  rx_error_bits = static_cast<uint16_t>(error ? (rx_error_bits | bit) : (rx_error_bits & ~bit));
  rx_lost_pending = false;
  rx_head = next;
}

ISR(USART_UDRE_vect) {
  const uint8_t tail = tx_tail;
  if (tail == tx_head) {
    UCSR0B &= static_cast<uint8_t>(~_BV(UDRIE0));
    return;
  }
  UDR0 = tx_buf[tail];
  tx_tail = static_cast<uint8_t>((tail + 1u) & (kUartTxRing - 1u));
}
