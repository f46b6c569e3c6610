// USART0 of the ATmega328P (D0/D1, the Uno's USB serial) for Modbus/RTU,
// without the Arduino core's HardwareSerial (its 2 x 64-byte buffers and
// vtable do not fit next to the gateway in 2 KB).
//
// Receive: the RX-complete interrupt stores each character with the time it
// arrived (micros() at the interrupt, i.e. at its stop bit), so the RTU
// framer sees true t1.5/t3.5 gaps however late the main loop reads them.
// Stamps are kept as 16 bits of micros()/4 (micros() counts in 4 us steps at
// 16 MHz) and widened when read: exact while the main loop reads each
// character within kStampRangeUs of its arrival.
// Transmit: a small ring drained by the data-register-empty interrupt; a
// response longer than the ring waits in write() for the rest to fit.
#pragma once
#include <stdint.h>

#include "modbus/byte_sink.h"
#include "modbus/parity.h"

namespace mb2co {
namespace avr {

/// Slots of the receive ring (one stays free: 15 characters, 1.3 ms of
/// back-to-back characters at 115200 baud; the main loop passes < 1 ms).
constexpr uint8_t kUartRxRing = 16;
/// Bytes the transmit ring holds: most responses (exceptions, write echoes,
/// reads of up to 12 registers) leave without waiting.
constexpr uint8_t kUartTxRing = 32;
/// How stale a received character may be before its stamp is ambiguous.
constexpr uint32_t kStampRangeUs = 4ul * 65536ul;  // 262 ms

struct UartCounters {
  uint16_t rx_lost;    ///< characters dropped: ring full or hardware overrun
  uint16_t rx_errors;  ///< characters with a framing or parity error
};

/// One received character. `error`: it was garbled (framing/parity) or
/// characters were lost just before it: the frame it belongs to is invalid.
struct UartChar {
  uint32_t stamp_us;
  uint8_t byte;
  bool error;
};

/// 8 data bits, 1 stop bit, `parity`. Call once from setup().
void uart_begin(uint32_t baud, modbus::Parity parity);
/// Takes the oldest received character; false when none is waiting.
bool uart_read(UartChar& out);
/// Queues `length` bytes (waits while the ring is full); always true.
bool uart_write(const uint8_t* data, uint16_t length);
/// A modbus::ByteSink on uart_write.
modbus::ByteSink uart_sink();
/// Counters since uart_begin (wrap at 2^16).
UartCounters uart_counters();

}  // namespace avr
}  // namespace mb2co
