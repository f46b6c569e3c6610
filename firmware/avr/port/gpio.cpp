#include "port/gpio.h"

#include <avr/interrupt.h>
#include <avr/io.h>

namespace mb2co {
namespace avr {
namespace {

// ATmega328P: PINx, DDRx and PORTx of one port are consecutive registers.
// (avr-gcc folds the register addresses; clang, which only checks this code
// for 16-bit-int hazards, does not.)
#ifndef __clang__
static_assert(&PINB + 1 == &DDRB && &DDRB + 1 == &PORTB, "port register layout");
#endif

struct Pin {
  volatile uint8_t* pin_reg;  ///< PINx; DDRx and PORTx follow
  uint8_t mask;
};

Pin pin_of(uint8_t pin) {
  // One shift for the three ports (a shift by a variable count is a loop on
  // the AVR).
  volatile uint8_t* reg = &PIND;
  if (pin >= 14) {
    reg = &PINC;
    pin = static_cast<uint8_t>(pin - 14);
  } else if (pin >= 8) {
    reg = &PINB;
    pin = static_cast<uint8_t>(pin - 8);
  }
  return Pin{reg, static_cast<uint8_t>(1u << pin)};
}

// Sets or clears `mask` in *reg with interrupts off (an ISR may write the port).
void update(volatile uint8_t* reg, uint8_t mask, bool set) {
  const uint8_t sreg = SREG;
  cli();
  if (set) {
    *reg = static_cast<uint8_t>(*reg | mask);
  } else {
    *reg = static_cast<uint8_t>(*reg & ~mask);
  }
  SREG = sreg;
}

}  // namespace

void gpio_output(uint8_t pin) {
  const Pin p = pin_of(pin);
  update(p.pin_reg + 1, p.mask, true);
}

void gpio_input(uint8_t pin, bool pullup) {
  const Pin p = pin_of(pin);
  update(p.pin_reg + 1, p.mask, false);
  update(p.pin_reg + 2, p.mask, pullup);
}

void gpio_write(uint8_t pin, bool high) {
  const Pin p = pin_of(pin);
  update(p.pin_reg + 2, p.mask, high);
}

bool gpio_read(uint8_t pin) {
  const Pin p = pin_of(pin);
  return (*p.pin_reg & p.mask) != 0;
}

}  // namespace avr
}  // namespace mb2co
