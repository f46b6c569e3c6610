#include "panel_channel.h"

#include <sstream>

#include "host/panel_command.h"

namespace mb2co {
namespace uno {

std::string PanelChannel::handle(const std::string& line, uint64_t now_us, uint32_t at_us) {
  const PanelCommand c = parse_panel_command(line, image_.buttons);
  if (c.kind == PanelCommand::kBlank) return std::string();
  if (c.kind == PanelCommand::kError) return "error " + c.error;
  if (c.kind == PanelCommand::kOther) {
    if (!c.rest.empty()) return "error unexpected '" + c.rest + "'";
    if (c.word == "leds?") return leds_line(at_us);
    if (c.word == "help") {
      return panel_help_lines(image_.buttons) +
             "\nhelp leds? | stack? | bus? | quit | help   (docs/uno-sim.md)";
    }
    if (c.word == "quit") {
      quit_ = true;
      return "bye";
    }
    if (image_.gateway && (c.word == "state?" || c.word == "counters?")) {
      return "error " + c.word + " needs the gateway's memory: on the Uno image read it over Modbus";
    }
    return "error unknown command '" + c.word + "' (help lists them)";
  }
  const uint8_t bit = static_cast<uint8_t>(1u << c.button);
  if (c.action == PanelCommand::kRelease) {
    buttons_ = static_cast<uint8_t>(buttons_ & ~bit);
    clicked_ = static_cast<uint8_t>(clicked_ & ~bit);
  } else {
    buttons_ = static_cast<uint8_t>(buttons_ | bit);
    clicked_ = static_cast<uint8_t>(c.action == PanelCommand::kClick ? (clicked_ | bit) : (clicked_ & ~bit));
    release_at_us_[c.button] = now_us + static_cast<uint64_t>(c.hold_ms) * 1000u;
  }
  return "ok";
}

void PanelChannel::process(uint64_t now_us) {
  for (int b = 0; b < image_.buttons.count; ++b) {
    const uint8_t bit = static_cast<uint8_t>(1u << b);
    if ((clicked_ & bit) && now_us >= release_at_us_[b]) {
      buttons_ = static_cast<uint8_t>(buttons_ & ~bit);
      clicked_ = static_cast<uint8_t>(clicked_ & ~bit);
    }
  }
}

void PanelChannel::set_led(uint8_t led, bool on, uint64_t now_us) {
  if (led >= kMaxLeds || leds_[led] == on) return;
  leds_[led] = on;
  const bool may_blink = (image_.blinking_leds >> led) & 1u;
  if (may_blink && led_changed_once_[led] && now_us - led_changed_us_[led] < kBlinkWindowUs)
    blinking_[led] = true;
  led_changed_us_[led] = now_us;
  led_changed_once_[led] = true;
}

bool PanelChannel::settle_blinks(uint64_t now_us) {
  bool settled = false;
  for (uint8_t i = 0; i < kMaxLeds; ++i) {
    if (blinking_[i] && now_us - led_changed_us_[i] >= kBlinkWindowUs) {
      blinking_[i] = false;
      settled = true;
    }
  }
  return settled;
}

std::string PanelChannel::leds_line(uint32_t at_us) const {
  std::ostringstream out;
  out << "leds";
  for (uint8_t i = 0; i < image_.led_count; ++i) {
    out << ' ' << image_.led_names[i] << '=';
    if (blinking_[i]) {
      out << "blink";
    } else {
      out << leds_[i];
    }
  }
  out << " at_us=" << at_us;
  return out.str();
}

}  // namespace uno
}  // namespace mb2co
