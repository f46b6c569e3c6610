// Arduino Uno pin numbers of the mb2co station: the SparkFun CAN-BUS shield
// (DEV-13262) plus the operator panel. docs/wiring.md has the table, the
// reasons for each choice and the shield's jumpers. Arduino pin numbers:
// D0..D13 are 0..13, A0..A5 are 14..19 (as A0..A5 in variants/standard).
#pragma once
#include <stdint.h>

namespace mb2co {
namespace pins {

// Taken by the Uno itself: D0/D1 = USB serial (Modbus/RTU), D11/D12/D13 = SPI.

// SparkFun CAN-BUS shield.
constexpr uint8_t kCanCs = 10;      ///< MCP2515 chip select (PB2, the AVR's SS)
constexpr uint8_t kCanInt = 2;      ///< MCP2515 INT, active low (INT0)
constexpr uint8_t kSdCs = 9;        ///< microSD chip select on the shield (slot kept empty)
constexpr uint8_t kShieldLed1 = 7;  ///< shield LED "D7", active high
constexpr uint8_t kShieldLed2 = 8;  ///< shield LED "D8", active high
// Joystick: each direction shorts its pin to GND (INPUT_PULLUP, low = pressed).
// Mapping of SparkFun's Joystick demo for this shield; older SK Pang sketches
// swap LEFT and RIGHT (A5/A2): see docs/wiring.md.
constexpr uint8_t kJoyUp = 15;     ///< A1
constexpr uint8_t kJoyLeft = 16;   ///< A2
constexpr uint8_t kJoyDown = 17;   ///< A3
constexpr uint8_t kJoyClick = 18;  ///< A4
constexpr uint8_t kJoyRight = 19;  ///< A5

// Operator panel: buttons to GND (INPUT_PULLUP, low = pressed), LEDs from the
// pin through 330-470 ohm to GND (high = on). Free pins are few: D3..D6 are
// free with the shield's LCD and GPS headers unused, A0 is free, and D9 (the
// microSD select) is free with the slot empty. A button sits on D9: its
// pull-up keeps a card that is inserted by mistake deselected except during
// a press, where an LED there would select the card half of the time.
constexpr uint8_t kButtonStart = 9;  ///< shares kSdCs: keep the microSD slot empty
constexpr uint8_t kButtonStop = 3;
constexpr uint8_t kButtonStop2 = 4;
constexpr uint8_t kLedRunSelf = 5;
constexpr uint8_t kLedRunPrev = 6;
constexpr uint8_t kLedRunNext = 14;  ///< A0

}  // namespace pins
}  // namespace mb2co
