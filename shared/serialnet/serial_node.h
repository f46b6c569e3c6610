// Wiring the unchanged node core to a SerialLink: the Node sends through
// link.can_sink() (give it to the Node's constructor) and receives through
//   link.set_receiver(node_receiver(node));
// Each pass: hand in bytes (link.on_byte), node.process(now), link.process(now).
#pragma once
#include "canopen/node.h"
#include "serialnet/serial_link.h"

namespace mb2co {
namespace serialnet {

/// A CanReceiver that hands every decoded frame to `node.receive` (`node`
/// must outlive the link's use of it).
inline CanReceiver node_receiver(canopen::Node& node) {
  return CanReceiver{[](void* ctx, const CanFrame& f, uint32_t now_us) {
                       static_cast<canopen::Node*>(ctx)->receive(f, now_us);
                     },
                     &node};
}

}  // namespace serialnet
}  // namespace mb2co
