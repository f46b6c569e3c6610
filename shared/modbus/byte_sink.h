// Where a Modbus/RTU port sends bytes: the whole contract between the
// portable Modbus code and a serial port (AVR UART, Linux tty/pty, simulator).
#pragma once
#include <stdint.h>

namespace mb2co {
namespace modbus {

/// Owned by the caller. `write` gets one complete ADU (CRC included) per call,
/// in transmission order; it may queue the bytes but must not keep `data`
/// after returning (the buffer is reused for the next frame). Returns false
/// when the bytes could not be queued: the response is lost and counted.
struct ByteSink {
  bool (*write)(void* ctx, const uint8_t* data, uint16_t length);
  void* ctx;
};

}  // namespace modbus
}  // namespace mb2co
