// The MCP2515 driver's SPI interface on the Uno: the hardware SPI unit at
// 8 MHz through its registers, chip select on pins::kCanCs.
#pragma once
#include "mcp2515.h"

namespace mb2co {
namespace avr {

uint8_t mcp2515_spi_transfer(void* ctx, uint8_t out);
void mcp2515_spi_select(void* ctx, bool active);

/// The driver's interface: constant function pointers, so a global Driver
/// built from it is constant-initialised (no constructor code).
constexpr mcp2515::Spi mcp2515_spi() {
  return mcp2515::Spi{&mcp2515_spi_transfer, &mcp2515_spi_select, nullptr};
}

/// Sets up SPI and the chip-select pin (high: deselected). Call once from
/// setup(), before Driver::begin().
void mcp2515_spi_begin();

}  // namespace avr
}  // namespace mb2co
