#include "uno_image.h"

namespace mb2co {
namespace uno {
namespace {

// firmware/avr/pins.h
const uint8_t kStationButtonPins[3] = {9, 3, 4};  // START, STOP, STOP2
const char* const kStationLeds[5] = {"self", "prev", "next", "lab", "canerr"};
const uint8_t kStationLedPins[5] = {5, 6, 14, 7, 8};
const uint8_t kStationNeighbourLeds = 0x06;  // prev, next: blink while unknown (line_app.h)

// mb2co-ionode's joystick, in the order of its 6000h/1 bits (ionode_main.cpp).
const char* const kJoystick[5] = {"UP", "DOWN", "LEFT", "RIGHT", "CLICK"};
const uint8_t kJoystickPins[5] = {15, 17, 16, 19, 18};  // A1, A3, A2, A5, A4
const char* const kShieldLeds[2] = {"d7", "d8"};
const uint8_t kShieldLedPins[2] = {7, 8};

const UnoImage kNone = {};

// The station's button names are panel_command.h's own (one list).
const UnoImage* images() {
  static const UnoImage kImages[] = {
      {"gateway", "mb2co-gateway.elf", panel_station_buttons(), kStationButtonPins, kStationLeds,
       kStationLedPins, 5, true, kStationNeighbourLeds},
      // The station plus FC 2Bh/0Dh (docs/gateway-network.md): the same board.
      {"network", "mb2co-gateway-network.elf", panel_station_buttons(), kStationButtonPins, kStationLeds,
       kStationLedPins, 5, true, kStationNeighbourLeds},
      {"ionode", "mb2co-ionode.elf", {kJoystick, 5}, kJoystickPins, kShieldLeds, kShieldLedPins, 2, false, 0},
      {"echo", "mcp2515-echo.elf", panel_station_buttons(), kStationButtonPins, kStationLeds, kStationLedPins,
       5, false, 0},
      kNone,
  };
  return kImages;
}

}  // namespace

const UnoImage* find_image(const std::string& name) {
  for (const UnoImage* i = images(); i->name != nullptr; ++i) {
    if (name == i->name) return i;
  }
  return nullptr;
}

const UnoImage& gateway_image() {
  return *find_image("gateway");
}

const UnoImage& ionode_image() {
  return *find_image("ionode");
}

std::string image_names() {
  std::string out;
  for (const UnoImage* i = images(); i->name != nullptr; ++i)
    out += (out.empty() ? "" : ", ") + std::string(i->name);
  return out;
}

}  // namespace uno
}  // namespace mb2co
