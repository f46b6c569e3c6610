// The parity bit of a serial character (Modbus over serial line V1.02
// §2.5.1: even by default; without parity the spec asks for two stop bits).
// One definition for the timing model, the AVR UART and the Linux serial port.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace modbus {

enum class Parity : uint8_t { kNone, kEven, kOdd };

}  // namespace modbus
}  // namespace mb2co
