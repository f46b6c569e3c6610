// Buttons and joystick switches to GND (INPUT_PULLUP): low = pressed.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace avr {

/// Sets every pin of pins[0..count) to INPUT_PULLUP.
void pullup_inputs(const uint8_t* pins, uint8_t count);
/// Bit i set when pins[i] reads low (pressed); count <= 8.
uint8_t read_pressed(const uint8_t* pins, uint8_t count);

}  // namespace avr
}  // namespace mb2co
