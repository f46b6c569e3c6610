// mb2co-gateway: one station of the line on an Arduino Uno with the SparkFun
// CAN-BUS shield. The portable gateway (shared/gateway: CANopen node, Modbus/
// RTU slave on the OD, RUN/STOP2 line application) on the Uno's ports:
//   CAN      MCP2515 (port/can_port.h): every frame to the gateway, which
//            routes it; the bit rate (2000h/2) and the filters as the core
//            sets them (shared/platform/device_port.h); built with FC 2Bh/0Dh
//            the filters stay open (Gateway::kWidestRange)
//   Modbus   USART0 = USB serial, 115200 8N1 (port/uart.h), stamped bytes
//   storage  EEPROM (port/eeprom_storage.h): 1010h save, node id at power-on
//   panel    START/STOP/STOP2 buttons, RUN-self/prev/next LEDs (pins.h);
//            shield LED D7 = lab LED (6200h/1 bit 0), D8 = CAN not usable
//            (no answer from the MCP2515, error passive or bus-off).
// Built by CMake (firmware/avr) or, through mb2co-gateway.ino, by the Arduino IDE
// (firmware/avr/README.md).
// The image brings its own main() and micros() (bottom of this file): the
// Arduino core's main() pulls in init() and the Timer0 interrupt of
// wiring.c, which also set up PWM timers, the ADC and millis() that the
// gateway never uses (-200 B of flash, the room the Uno lacks).
#include <Arduino.h>
#include <avr/interrupt.h>
#include <avr/io.h>

#include "gateway/gateway.h"
#include "mcp2515.h"
#include "pins.h"
#include "port/can_int.h"
#include "port/can_port.h"
#include "port/eeprom_storage.h"
#include "port/gpio.h"
#include "port/mcp2515_spi.h"
#include "port/pressed.h"
#include "port/uart.h"

namespace {

using namespace mb2co;

constexpr uint32_t kBaud = 115200;
constexpr modbus::Parity kParity = modbus::Parity::kNone;
/// Node id (and Modbus address 1) until one is saved in EEPROM (2000h/1).
constexpr uint8_t kDefaultNodeId = 1;

mcp2515::Driver driver(avr::mcp2515_spi());
using CanPort = avr::CanPortFor<gateway::Gateway::kWidestRange>;
CanPort can_port(driver);
const canopen::ParamStorage storage = avr::eeprom_storage();
gateway::Gateway gw(gateway::GatewayPorts{CanSink{&CanPort::send_to, &can_port}, avr::uart_sink(), &storage,
                                          kBaud, &CanPort::kControl});

// Button bits 0..2 (gateway::Button) and LED bits 0..3 (gateway::Led).
const uint8_t kButtonPins[3] = {pins::kButtonStart, pins::kButtonStop, pins::kButtonStop2};
const uint8_t kLedPins[4] = {pins::kLedRunSelf, pins::kLedRunPrev, pins::kLedRunNext, pins::kShieldLed1};
uint8_t leds_shown = 0xFF;
bool can_led_shown = false;

void show_leds(uint8_t leds) {
  if (leds == leds_shown) return;
  leds_shown = leds;
  // One bit per LED shifted down: a shift by a variable count is a loop on
  // the AVR.
  for (uint8_t i = 0, bits = leds; i < 4; ++i, bits = static_cast<uint8_t>(bits >> 1)) {
    avr::gpio_write(kLedPins[i], bits & 1u);
  }
}

void show_can_state() {
  const bool bad = !can_port.ready() || driver.error_state() >= mcp2515::ErrorState::kPassive;
  if (bad == can_led_shown) return;
  can_led_shown = bad;
  avr::gpio_write(pins::kShieldLed2, bad);
}

}  // namespace

void setup() {
  avr::pullup_inputs(kButtonPins, 3);
  for (uint8_t pin : kLedPins) avr::gpio_output(pin);
  avr::gpio_output(pins::kShieldLed2);
  avr::gpio_input(pins::kCanInt, false);  // the MCP2515 drives INT push-pull
  avr::uart_begin(kBaud, kParity);
  avr::mcp2515_spi_begin();
  // Starts the chip at the saved bit rate before the boot-up message
  // (Gateway::on_reset: CanControl::set_bitrate).
  gw.start(micros(), kDefaultNodeId);
}

void loop() {
  // `now` is taken before the serial port is drained: no byte stamped before
  // it is left unread when the Modbus slave decides on t3.5.
  const uint32_t now_us = micros();
  avr::UartChar c;
  // A garbled character's byte lands in a frame that is then discarded.
  while (avr::uart_read(c)) gw.modbus_slave().on_char(c.byte, c.stamp_us, c.error);
  can_port.poll(gw.can_input(), avr::can_int_low(), now_us);
  show_leds(gw.process(now_us, avr::read_pressed(kButtonPins, 3)));
  show_can_state();
}

// ---- the clock and main(), in place of the Arduino core's -------------------
// Timer0 as the core's init() sets it (fast PWM, clock / 64: one tick 4 us,
// an overflow every 1024 us) and micros() as the core's (wiring.c), without
// millis(): the overflow interrupt only counts.
// The core's name: port/uart.cpp reads it for its stamps.
volatile unsigned long timer0_overflow_count = 0;

ISR(TIMER0_OVF_vect) {
  timer0_overflow_count = timer0_overflow_count + 1;
}

unsigned long micros() {
  const uint8_t sreg = SREG;
  cli();
  uint32_t overflows = timer0_overflow_count;
  const uint8_t ticks = TCNT0;
  // An overflow not yet counted (interrupts are off): the counter wrapped.
  if ((TIFR0 & _BV(TOV0)) && ticks < 255) ++overflows;
  SREG = sreg;
  return ((overflows << 8) + ticks) * (64 / clockCyclesPerMicrosecond());
}

int main() {
  sei();
  TCCR0A = _BV(WGM01) | _BV(WGM00);
  TCCR0B = _BV(CS01) | _BV(CS00);
  TIMSK0 = _BV(TOIE0);
  UCSR0B = 0;  // the bootloader's use of the serial port ends here (as init())
  setup();
  for (;;) loop();
}
