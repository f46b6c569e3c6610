#include "port/pressed.h"

#include "port/gpio.h"

namespace mb2co {
namespace avr {

void pullup_inputs(const uint8_t* pins, uint8_t count) {
  for (uint8_t i = 0; i < count; ++i) gpio_input(pins[i], true);
}

uint8_t read_pressed(const uint8_t* pins, uint8_t count) {
  // The bit walks by a shift of one: a shift by a variable count is a loop
  // on the AVR.
  uint8_t bits = 0;
  for (uint8_t i = 0, bit = 1; i < count; ++i, bit = static_cast<uint8_t>(bit << 1)) {
    if (!gpio_read(pins[i])) bits = static_cast<uint8_t>(bits | bit);
  }
  return bits;
}

}  // namespace avr
}  // namespace mb2co
