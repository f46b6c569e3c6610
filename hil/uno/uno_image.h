// The images mb2co-uno runs (--image NAME) and what their pins mean on the
// board (firmware/avr/pins.h): the gateway's operator panel, or the I/O
// node's joystick and shield LEDs. One table, read by the rig (which pins
// to drive and watch), the panel (the names on stdin/stdout) and the
// command line (the file in the build's avr directory).
#pragma once
#include <stdint.h>

#include <string>

#include "host/panel_command.h"

namespace mb2co {
namespace uno {

struct UnoImage {
  const char* name;              ///< --image NAME
  const char* elf;               ///< file name in the build's avr directory
  PanelButtons buttons;          ///< panel names, index = bit of the pressed mask
  const uint8_t* button_pins;    ///< Arduino pin of each button (to GND: low = pressed)
  const char* const* led_names;  ///< the `leds` line's fields, in order
  const uint8_t* led_pins;       ///< Arduino pin of each LED (high = on)
  uint8_t led_count;
  /// The image is the gateway: `state?`/`counters?` are Modbus registers there.
  bool gateway;
  /// Bit i: LED i may blink (the gateway's prev/next while that neighbour is
  /// unknown, 250 ms on, 250 ms off); the panel shows it as "blink".
  uint8_t blinking_leds;
};

/// The gateway (mb2co-gateway.elf): buttons D9 START, D3 STOP, D4 STOP2;
/// LEDs D5 self, D6 prev, D14 next, D7 lab, D8 canerr.
const UnoImage& gateway_image();
/// The CiA 401 I/O node (mb2co-ionode.elf): joystick A1 UP, A3 DOWN,
/// A2 LEFT, A5 RIGHT, A4 CLICK (6000h/1 bits 0-4); LEDs D7, D8 (6200h/1
/// bits 0, 1).
const UnoImage& ionode_image();
/// The image named `name` (gateway, ionode; network: the network gateway
/// mb2co-gateway-network.elf, echo: mcp2515-echo.elf, both on the gateway's
/// wiring), nullptr for another name.
const UnoImage* find_image(const std::string& name);
/// "gateway, network, ionode, echo"
std::string image_names();

}  // namespace uno
}  // namespace mb2co
