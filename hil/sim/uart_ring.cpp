#include "sim/uart_ring.h"

#include "modbus/rtu_timing.h"

namespace mb2co {
namespace sim {

UartRing::UartRing(uint32_t baud, uint32_t capacity) : capacity_(capacity) {
  const modbus::RtuTiming rtu = modbus::rtu_timing(baud);
  frame_gap_ns_ = (rtu.t35_us + rtu.char_us) * kNsPerUs;
}

}  // namespace sim
}  // namespace mb2co
