// The parity bit of a serial character (Modbus over serial line V1.02
// §2.5.1: even by default; without parity the spec asks for two stop bits).
// One definition for the timing model, the AVR UART, the Linux serial port,
// the command lines and libmodbus's letter.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace modbus {

enum class Parity : uint8_t { kNone, kEven, kOdd };

/// 'N', 'E' or 'O': the letter of "8N1", of libmodbus's modbus_new_rtu and of
/// mbpoll's -P.
constexpr char parity_letter(Parity parity) {
  return parity == Parity::kEven ? 'E' : parity == Parity::kOdd ? 'O' : 'N';
}

}  // namespace modbus
}  // namespace mb2co
