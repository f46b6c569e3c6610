// One classic CAN frame and the sink frames leave through: the whole contract
// between the portable core and a CAN port (MCP2515, SocketCAN, simulator).
#pragma once
#include <stdint.h>

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

/// Where frames to transmit go. Owned by the caller; `send` must not block.
/// Returns false when the port's transmit queue is full: the frame is dropped
/// and the caller decides whether to retry (services count such drops).
struct CanSink {
  bool (*send)(void* ctx, const CanFrame& frame);
  void* ctx;
};

}  // namespace mb2co
