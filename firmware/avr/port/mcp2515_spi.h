// The MCP2515 driver's SPI interface on the Uno: hardware SPI through the
// Arduino SPI library, chip select on pins::kCanCs.
#pragma once
#include "mcp2515.h"

namespace mb2co {
namespace avr {

/// The driver's interface: constant function pointers, safe to take during
/// static initialisation (a global Driver can be built from it).
mcp2515::Spi mcp2515_spi();

/// Sets up SPI and the chip-select pin (high: deselected). Call once from
/// setup(), before Driver::begin().
void mcp2515_spi_begin();

}  // namespace avr
}  // namespace mb2co
