// The gateway's FC 2Bh / MEI 0Dh member, by the image's profile
// (profiles/profile.h, MB2CO_CONFIG_NETWORK): the network service where the
// profile has it, an empty stand-in elsewhere whose calls compile to
// nothing. The gateway holds a NetworkSlot and calls it unconditionally, so
// the switch is tested here, in the service's own code, and nowhere in the
// gateway.
#pragma once
#include <stdint.h>

#include "profiles/profile.h"

#if MB2CO_CONFIG_NETWORK
#include "gateway/network_service.h"

namespace mb2co {
namespace gateway {
typedef NetworkService NetworkSlot;
}  // namespace gateway
}  // namespace mb2co

#else
#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/node.h"
#include "canopen/od.h"
#include "modbus/slave.h"

namespace mb2co {
namespace gateway {

/// No FC 2Bh/0Dh in this image: the slave answers it with exception 01
/// (no handler is attached); NetworkService's calls, doing nothing.
class NetworkSlot {
 public:
  NetworkSlot(canopen::Node&, canopen::ObjectDictionary&, modbus::SlaveCore&, const uint32_t&,
              const uint8_t&) {}
  void attach() {}
  void on_can_frame(const CanFrame&, uint32_t) {}
  void process(uint32_t) {}
  void next_deadline(NextDeadline&) const {}
};

}  // namespace gateway
}  // namespace mb2co
#endif
