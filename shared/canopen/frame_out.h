// Building a frame to send, shared by every service that transmits (boot-up,
// heartbeat, EMCY, SYNC, SDO, TPDO): one copy of this code in the image.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"

namespace mb2co {
namespace canopen {

/// Sends the standard data frame `id` with `dlc` (0..8) bytes of `data`
/// (nullptr: zeros); the rest of the payload is zero. Returns the sink's
/// answer (false: the port refused the frame).
bool send_frame(const CanSink& sink, uint16_t id, uint8_t dlc, const uint8_t* data);

}  // namespace canopen
}  // namespace mb2co
