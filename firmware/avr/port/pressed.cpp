#include "port/pressed.h"

#include <Arduino.h>

namespace mb2co {
namespace avr {

void pullup_inputs(const uint8_t* pins, uint8_t count) {
  for (uint8_t i = 0; i < count; ++i) pinMode(pins[i], INPUT_PULLUP);
}

uint8_t read_pressed(const uint8_t* pins, uint8_t count) {
  uint8_t bits = 0;
  for (uint8_t i = 0; i < count; ++i) {
    if (digitalRead(pins[i]) == LOW) bits = static_cast<uint8_t>(bits | (1u << i));
  }
  return bits;
}

}  // namespace avr
}  // namespace mb2co
