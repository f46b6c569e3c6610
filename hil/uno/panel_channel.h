// The operator panel of the simulated Uno on stdin/stdout, with mb2co-node's
// line protocol (docs/mb2co-node.md) where the Uno has the same thing:
//   press B | release B | click B [ms]   (B: the image's buttons: START,
//                                         STOP, STOP2; the I/O node's UP,
//                                         DOWN, LEFT, RIGHT, CLICK) -> "ok"
//   leds?  -> "leds self=1 prev=0 next=1 lab=0 canerr=0 at_us=T"
//             (the I/O node: "leds d7=1 d8=0 at_us=T")
//   quit   -> "bye"
// state? and counters? read the gateway's memory in mb2co-node; on the Uno
// image that is over Modbus only: they get "error ...". A "leds" line also
// comes unasked whenever what a LED shows changes. A LED that may blink
// (UnoImage::blinking_leds) and changes again within kBlinkWindowUs shows
// "blink", as in mb2co-node, until it rests that long: one line when a
// blink starts and one when it ends, not one at every 250 ms toggle.
// Button levels are what the pins see (low = pressed); the image debounces
// them itself.
#pragma once
#include <stdint.h>

#include <string>

#include "uno_image.h"

namespace mb2co {
namespace uno {

class PanelChannel {
 public:
  static const uint8_t kMaxButtons = 8;
  static const uint8_t kMaxLeds = 8;
  /// The gateway's blink half-period (line_app.h, 250 ms) and a margin for
  /// its main loop: two changes closer than this are a blink.
  static const uint32_t kBlinkWindowUs = 300000;

  /// The buttons and LEDs of `image` (kept by reference: a static table).
  explicit PanelChannel(const UnoImage& image = gateway_image()) : image_(image) {}

  /// Handles one line at simulated time `now_us` (`at_us`: the same moment
  /// on the wall clock, for the leds reply); the reply without newline ("" for
  /// a blank line).
  std::string handle(const std::string& line, uint64_t now_us, uint32_t at_us);
  /// Releases clicked buttons whose time is up.
  void process(uint64_t now_us);
  /// Bit i: button i of the image (gateway: 0 START, 1 STOP, 2 STOP2) is pressed.
  uint8_t buttons() const { return buttons_; }
  bool quit() const { return quit_; }

  /// LED `led` (index into the image's LEDs) shows `on` from simulated `now_us`.
  void set_led(uint8_t led, bool on, uint64_t now_us);
  /// Ends the blinks that rested kBlinkWindowUs by `now_us`; true if any did
  /// (the leds line changed).
  bool settle_blinks(uint64_t now_us);
  /// "leds ..." stamped `at_us` ("blink" for a blinking LED).
  std::string leds_line(uint32_t at_us) const;

 private:
  const UnoImage& image_;
  uint8_t buttons_ = 0;
  uint8_t clicked_ = 0;  ///< buttons a click will release
  uint64_t release_at_us_[kMaxButtons] = {};
  bool leds_[kMaxLeds] = {};
  uint64_t led_changed_us_[kMaxLeds] = {};
  bool led_changed_once_[kMaxLeds] = {};  ///< led_changed_us_ holds a change
  bool blinking_[kMaxLeds] = {};
  bool quit_ = false;
};

}  // namespace uno
}  // namespace mb2co
