// A request that reaches SlaveCore through another framer than its RTU one:
// one per Modbus/TCP connection (modbus/tcp_framer.h frames it). The slave
// borrows the channel while it serves the request and, when the answer is
// deferred (FC 2Bh/0Dh to another node), until that answer is sent or the
// channel is forgotten (SlaveCore::serve, SlaveCore::forget).
#pragma once
#include <stdint.h>

#include "modbus/protocol.h"

namespace mb2co {
namespace modbus {

/// The largest PDU on any transport (application protocol §4.1: 253 bytes,
/// what a 256-byte RTU ADU carries).
constexpr uint16_t kMaxPduBytes = kMaxAduBytes - 1u - kCrcBytes;

struct PduChannel {
  /// The request PDU (function code first), then the response built in
  /// place: kMaxPduBytes bytes, owned by the caller, unmoved while the
  /// slave holds the channel.
  uint8_t* pdu;
  /// Takes a response PDU (no address, no CRC); false when it cannot (a
  /// closed connection): counted as a send failure, like the line's sink.
  bool (*send)(void* ctx, const uint8_t* pdu, uint16_t length);
  void* ctx;
};

}  // namespace modbus
}  // namespace mb2co
