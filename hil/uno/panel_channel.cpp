#include "panel_channel.h"

#include <stdlib.h>

#include <sstream>

namespace mb2co {
namespace uno {
namespace {

int button_index(const std::string& name) {
  if (name == "START") return 0;
  if (name == "STOP") return 1;
  if (name == "STOP2") return 2;
  return -1;
}

}  // namespace

std::string PanelChannel::handle(const std::string& line, uint64_t now_us, uint32_t at_us) {
  std::istringstream in(line);
  std::string cmd, arg, extra;
  in >> cmd >> arg;
  if (cmd.empty()) return std::string();
  if (cmd == "leds?" && arg.empty()) return leds_line(at_us);
  if (cmd == "quit" && arg.empty()) {
    quit_ = true;
    return "bye";
  }
  if (cmd == "state?" || cmd == "counters?") {
    return "error " + cmd + " needs the gateway's memory: on the Uno image read it over Modbus";
  }
  if (cmd != "press" && cmd != "release" && cmd != "click") return "error unknown command '" + cmd + "'";
  const int b = button_index(arg);
  if (b < 0) return "error unknown button '" + arg + "' (START, STOP, STOP2)";
  const uint8_t bit = static_cast<uint8_t>(1u << b);
  long ms = 100;
  if (cmd == "click" && (in >> extra)) {
    char* end = nullptr;
    ms = strtol(extra.c_str(), &end, 10);
    if (*end != '\0' || ms < 1 || ms > 60000) return "error bad click time '" + extra + "' (1..60000 ms)";
  } else if (in >> extra) {
    return "error unexpected '" + extra + "'";
  }
  if (cmd == "release") {
    buttons_ = static_cast<uint8_t>(buttons_ & ~bit);
    clicked_ = static_cast<uint8_t>(clicked_ & ~bit);
  } else {
    buttons_ = static_cast<uint8_t>(buttons_ | bit);
    clicked_ = static_cast<uint8_t>(cmd == "click" ? (clicked_ | bit) : (clicked_ & ~bit));
    release_at_us_[b] = now_us + static_cast<uint64_t>(ms) * 1000u;
  }
  return "ok";
}

void PanelChannel::process(uint64_t now_us) {
  for (int b = 0; b < 3; ++b) {
    const uint8_t bit = static_cast<uint8_t>(1u << b);
    if ((clicked_ & bit) && now_us >= release_at_us_[b]) {
      buttons_ = static_cast<uint8_t>(buttons_ & ~bit);
      clicked_ = static_cast<uint8_t>(clicked_ & ~bit);
    }
  }
}

void PanelChannel::set_led(Led led, bool on) {
  leds_[led] = on;
}

std::string PanelChannel::leds_line(uint32_t at_us) const {
  std::ostringstream out;
  out << "leds self=" << leds_[kSelf] << " prev=" << leds_[kPrev] << " next=" << leds_[kNext]
      << " lab=" << leds_[kLab] << " canerr=" << leds_[kCanErr] << " at_us=" << at_us;
  return out.str();
}

}  // namespace uno
}  // namespace mb2co
