// mb2co-ionode: a minimal CANopen node on an Arduino Uno with the SparkFun
// CAN-BUS shield: the CiA 401 I/O node of shared/ionode (docs/od-ionode.md).
//   6000h/1  joystick (bit 0 UP, 1 DOWN, 2 LEFT, 3 RIGHT, 4 CLICK; 1 = pressed),
//            debounced by 2101h, published by TPDO1 on change
//   6200h/1  outputs from RPDO1 or SDO: bit 0 shield LED D7, bit 1 LED D8
//   2001h/1  node id (default kDefaultNodeId), 2001h/2 bit rate (default 500
//            kbit/s): written by SDO, saved in EEPROM with 1010h (the gateway's
//            two-slot layout), in force from the next reset (docs/labs.md)
// Built by CMake (firmware/avr) or, through mb2co-ionode.ino, by the Arduino IDE
// (firmware/avr/README.md).
#include <Arduino.h>

#include "ionode/io_node.h"
#include "mcp2515.h"
#include "pins.h"
#include "port/can_int.h"
#include "port/can_port.h"
#include "port/eeprom_storage.h"
#include "port/gpio.h"
#include "port/mcp2515_spi.h"
#include "port/pressed.h"

namespace {

using namespace mb2co;

/// The node id without a saved one (a fresh board: set each board's own id
/// by SDO before two of them share a bus).
constexpr uint8_t kDefaultNodeId = 0x20;

mcp2515::Driver driver(avr::mcp2515_spi());
const canopen::ParamStorage storage = avr::eeprom_storage();
using CanPort = avr::CanPortFor<ionode::IoNode::kWidestRange>;
CanPort can_port(driver);
ionode::IoNode io(CanSink{&CanPort::send_to, &can_port});

const uint8_t kJoystickPins[5] = {pins::kJoyUp, pins::kJoyDown, pins::kJoyLeft, pins::kJoyRight,
                                  pins::kJoyClick};
uint8_t raw_inputs = 0;     ///< last sampled levels
uint8_t stable_inputs = 0;  ///< debounced levels, as in 6000h/1
uint32_t raw_since_us = 0;  ///< when raw_inputs last changed
uint8_t outputs_shown = 0xFF;

// A level counts once it held for the debounce time 2101h (ms).
void sample_inputs(uint32_t now_us) {
  const uint8_t raw = avr::read_pressed(kJoystickPins, 5);
  if (raw != raw_inputs) {
    raw_inputs = raw;
    raw_since_us = now_us;
  }
  canopen::ObjectDictionary& od = io.od();
  const uint32_t debounce_us = 1000ul * od.get(od.find(0x2101, 0));
  if (raw_inputs != stable_inputs && now_us - raw_since_us >= debounce_us) {
    stable_inputs = raw_inputs;
    io.set_input(0, stable_inputs);
  }
}

void show_outputs() {
  const uint8_t out = io.output(0);
  if (out == outputs_shown) return;
  outputs_shown = out;
  avr::gpio_write(pins::kShieldLed1, (out & 0x01) != 0);
  avr::gpio_write(pins::kShieldLed2, (out & 0x02) != 0);
}

}  // namespace

void setup() {
  avr::pullup_inputs(kJoystickPins, 5);
  avr::gpio_output(pins::kShieldLed1);
  avr::gpio_output(pins::kShieldLed2);
  avr::gpio_input(pins::kCanInt, false);  // the MCP2515 drives INT push-pull
  avr::mcp2515_spi_begin();
  io.node().set_storage(&storage);
  // Starts the chip at the saved bit rate before the boot-up message
  // (IoNode::on_reset: CanControl::set_bitrate), and sets its filters.
  io.node().set_can_control(&CanPort::kControl);
  io.start(kDefaultNodeId, micros());
}

void loop() {
  const uint32_t now_us = micros();
  can_port.poll(io.can_input(), avr::can_int_low(), now_us);
  sample_inputs(now_us);
  io.process(now_us);
  show_outputs();
}
