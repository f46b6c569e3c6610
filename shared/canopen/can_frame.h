// One classic CAN frame, the unit handed between the core and a CAN port.
// The contract with the port (CanSink, CanControl) is platform/device_port.h.
#pragma once
#include <stdint.h>

#include "platform/device_port.h"

namespace mb2co {

/// A classic CAN 2.0 frame. Plain data: safe to copy inside an ISR.
struct CanFrame {
  enum : uint8_t { kRtr = 0x01, kExtended = 0x02 };
  uint32_t id;      ///< 11-bit, or 29-bit when kExtended is set; no flag bits in here
  uint8_t dlc;      ///< data length code 0..8 (also for RTR frames)
  uint8_t flags;    ///< kRtr | kExtended
  uint8_t data[8];  ///< bytes beyond dlc are unspecified

  bool rtr() const { return (flags & kRtr) != 0; }
  bool extended() const { return (flags & kExtended) != 0; }
};

}  // namespace mb2co
