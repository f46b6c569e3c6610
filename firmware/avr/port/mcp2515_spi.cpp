#include "mcp2515_spi.h"

#include <Arduino.h>
#include <SPI.h>

#include "pins.h"

namespace mb2co {
namespace avr {
namespace {

// Mode 0, MSB first. 8 MHz is F_CPU / 2, the AVR's fastest SPI clock and
// below the MCP2515's 10 MHz limit.
const SPISettings kSettings(8000000, MSBFIRST, SPI_MODE0);

// Chip select by direct port access: digitalWrite costs ~4 us per call,
// more than the 13 bytes of a frame take on the wire at 8 MHz.
volatile uint8_t* cs_port;
uint8_t cs_mask;

uint8_t transfer(void*, uint8_t out) { return SPI.transfer(out); }

void select(void*, bool active) {
  if (active) {
    SPI.beginTransaction(kSettings);
    *cs_port &= static_cast<uint8_t>(~cs_mask);
  } else {
    *cs_port |= cs_mask;
    SPI.endTransaction();
  }
}

}  // namespace

mcp2515::Spi mcp2515_spi() { return mcp2515::Spi{&transfer, &select, nullptr}; }

void mcp2515_spi_begin() {
  pinMode(pins::kCanCs, OUTPUT);
  digitalWrite(pins::kCanCs, HIGH);
  cs_port = portOutputRegister(digitalPinToPort(pins::kCanCs));
  cs_mask = digitalPinToBitMask(pins::kCanCs);
  SPI.begin();
}

}  // namespace avr
}  // namespace mb2co
