#include "port/pressed.h"

#include "port/gpio.h"

namespace mb2co {
namespace avr {

void pullup_inputs(const uint8_t* pins, uint8_t count) {
  for (uint8_t i = 0; i < count; ++i) gpio_input(pins[i], true);
}

uint8_t read_pressed(const uint8_t* pins, uint8_t count) {
  uint8_t bits = 0;
  for (uint8_t i = 0; i < count; ++i) {
    if (!gpio_read(pins[i])) bits = static_cast<uint8_t>(bits | (1u << i));
  }
  return bits;
}

}  // namespace avr
}  // namespace mb2co
