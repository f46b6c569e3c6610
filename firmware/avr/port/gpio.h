// Digital pins of the Uno by Arduino number (D0..D13 = 0..13, A0..A5 =
// 14..19) by direct port access: what pinMode/digitalWrite/digitalRead do for
// our pins, without their pin tables and PWM bookkeeping (-0.3 KB of flash;
// no pin of ours is used with analogWrite, so there is no PWM to turn off).
// Read-modify-writes of a port run with interrupts off, as in the core.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace avr {

void gpio_output(uint8_t pin);
/// Input, with the internal pull-up when `pullup` (INPUT_PULLUP) or without (INPUT).
void gpio_input(uint8_t pin, bool pullup);
void gpio_write(uint8_t pin, bool high);
bool gpio_read(uint8_t pin);

}  // namespace avr
}  // namespace mb2co
