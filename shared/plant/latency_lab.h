// The latency-lab control process of seed 000 §11: read a button, write its
// state to an LED. The LED follows the button sampled in the same cycle, so
// the press-to-LED delay measured around it is all transport (Modbus, and
// CANopen when the button sits on another node), never this logic.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace plant {

class ButtonToLed {
 public:
  /// One cycle: the LED state to write for the button state just read.
  bool step(bool button_pressed) {
    if (button_pressed != led_) {
      if (button_pressed)
        ++presses_;
      else
        ++releases_;
    }
    led_ = button_pressed;
    return led_;
  }
  bool led() const { return led_; }
  /// Changes seen at the sampling points (a press shorter than one cycle is
  /// invisible here, which is what the lab measures).
  uint32_t presses() const { return presses_; }
  uint32_t releases() const { return releases_; }

 private:
  bool led_ = false;
  uint32_t presses_ = 0;
  uint32_t releases_ = 0;
};

}  // namespace plant
}  // namespace mb2co
