// The MCP2515's INT line on the Uno (pins::kCanInt, active low), read once a
// loop pass for avr::CanPort::poll (which stays portable without it).
#pragma once
#include <avr/io.h>

#include "pins.h"

namespace mb2co {
namespace avr {

static_assert(pins::kCanInt == 2, "INT is read from PIND2 below");

/// True while the chip signals a received frame or an error.
inline bool can_int_low() {
  return (PIND & _BV(PIND2)) == 0;
}

}  // namespace avr
}  // namespace mb2co
