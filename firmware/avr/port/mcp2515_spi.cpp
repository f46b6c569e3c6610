#include "mcp2515_spi.h"

#include <avr/io.h>

#include "pins.h"
#include "port/gpio.h"

namespace mb2co {
namespace avr {
namespace {

// The MCP2515 is the only SPI device: the SPI unit is set up once (mode 0,
// MSB first, F_CPU / 2 = 8 MHz, the AVR's fastest clock and below the chip's
// 10 MHz) and used through its registers, without the Arduino SPI library
// (its begin() pulls in pinMode and the pin tables; its transactions would
// rewrite the same settings for every instruction).
// Chip select by direct port access (one sbi/cbi): digitalWrite costs ~4 us
// per call, more than the 13 bytes of a frame take on the wire at 8 MHz.
static_assert(pins::kCanCs == 10, "CS is driven as PB2 (the AVR's SS) below");

}  // namespace

uint8_t mcp2515_spi_transfer(void*, uint8_t out) {
  SPDR = out;
  while (!(SPSR & _BV(SPIF))) {
  }
  return SPDR;
}

void mcp2515_spi_select(void*, bool active) {
  if (active) {
    PORTB &= static_cast<uint8_t>(~_BV(PORTB2));
  } else {
    PORTB |= _BV(PORTB2);
  }
}

void mcp2515_spi_begin() {
  // SS (D10) an output before master mode: as an input pulled low it would
  // switch the SPI unit back to slave mode.
  gpio_write(pins::kCanCs, true);  // deselected before it becomes an output
  gpio_output(pins::kCanCs);
  gpio_output(13);  // SCK (PB5)
  gpio_output(11);  // MOSI (PB3); MISO (PB4) stays an input
  SPCR = _BV(SPE) | _BV(MSTR);
  SPSR = _BV(SPI2X);
}

}  // namespace avr
}  // namespace mb2co
