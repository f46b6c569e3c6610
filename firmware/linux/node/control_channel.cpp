#include "control_channel.h"

#include <cstdlib>
#include <sstream>

#include "canopen/clock.h"

namespace mb2co {
namespace node {

namespace {

const uint8_t kButtons[3] = {gateway::kStart, gateway::kStop, gateway::kStop2};
const char* const kButtonNames[3] = {"START", "STOP", "STOP2"};

int button_index(const std::string& name) {
  for (int i = 0; i < 3; ++i) {
    if (name == kButtonNames[i]) return i;
  }
  return -1;
}

std::string stamped(const std::string& text, uint32_t now_us) {
  return text + " at_us=" + std::to_string(now_us);
}

}  // namespace

std::string ControlChannel::leds_text(uint8_t leds) {
  std::ostringstream s;
  s << "leds self=" << ((leds & gateway::kLedRunSelf) ? 1 : 0)
    << " prev=" << ((leds & gateway::kLedRunPrev) ? 1 : 0)
    << " next=" << ((leds & gateway::kLedRunNext) ? 1 : 0) << " lab=" << ((leds & gateway::kLedLab) ? 1 : 0);
  return s.str();
}

std::string ControlChannel::state_text() {
  canopen::ObjectDictionary& od = gw_.od();
  auto get = [&](canopen::OdKey key) { return od.get(od.find(key)); };
  namespace e = gateway::od::GatewayEntry;
  std::ostringstream s;
  s << "state node=" << unsigned(gw_.node_id()) << " nmt=" << get(e::x2002_0_nmtState)
    << " run=" << get(e::x2100_2_runState) << " cause=" << get(e::x2100_4_stopCause)
    << " stop2=" << get(e::x2100_3_stop2Count) << " prev=" << get(e::x2110_4_prevNodeId) << ':'
    << get(e::x2110_3_prevStatus) << ':' << get(e::x2110_1_prevRunState)
    << " next=" << get(e::x2120_4_nextNodeId) << ':' << get(e::x2120_3_nextStatus) << ':'
    << get(e::x2120_1_nextRunState);
  return s.str();
}

std::string ControlChannel::counters_text() {
  const modbus::DiagCounters& c = gw_.modbus_slave().counters();
  std::ostringstream s;
  s << "counters bus=" << c.bus_messages << " comm=" << c.bus_comm_errors << " exc=" << c.exceptions
    << " srv=" << c.server_messages << " noresp=" << c.no_responses << " ovr=" << c.char_overruns;
  return s.str();
}

std::string ControlChannel::events(uint8_t leds, uint32_t now_us) {
  std::string out;
  const std::string l = leds_text(leds);
  if (l != leds_shown_) out += stamped(l, now_us) + '\n';
  leds_shown_ = l;
  const std::string s = state_text();
  if (s != state_shown_) out += stamped(s, now_us) + '\n';
  state_shown_ = s;
  return out;
}

std::string ControlChannel::handle(const std::string& line, uint32_t now_us) {
  std::istringstream in(line);
  std::string cmd, arg;
  in >> cmd >> arg;
  if (cmd.empty()) return std::string();
  if (cmd == "leds?") {
    const canopen::ObjectDictionary& od = gw_.od();
    return stamped(leds_text(static_cast<uint8_t>(od.get(od.find(gateway::od::GatewayEntry::x2200_0_leds)))),
                   now_us);
  }
  if (cmd == "state?") return stamped(state_text(), now_us);
  if (cmd == "counters?") return counters_text();
  if (cmd == "quit") {
    quit_ = true;
    return "bye";
  }
  if (cmd != "press" && cmd != "release" && cmd != "click") return "error unknown command '" + cmd + "'";
  const int i = button_index(arg);
  if (i < 0) return "error unknown button '" + arg + "' (START, STOP, STOP2)";
  const uint8_t bit = kButtons[i];
  if (cmd == "release") {
    buttons_ = static_cast<uint8_t>(buttons_ & ~bit);
    clicked_ = static_cast<uint8_t>(clicked_ & ~bit);
    return "ok";
  }
  if (cmd == "click") {
    long ms = 100;  // without a duration
    std::string word;
    if (in >> word) {
      char* end = nullptr;
      ms = std::strtol(word.c_str(), &end, 10);
      if (*end != '\0' || ms < 1 || ms > 60000)
        return "error bad click duration '" + word + "' (1..60000 ms)";
    }
    clicked_ = static_cast<uint8_t>(clicked_ | bit);
    release_at_us_[i] = now_us + static_cast<uint32_t>(ms) * 1000u;
  }
  buttons_ = static_cast<uint8_t>(buttons_ | bit);
  return "ok";
}

void ControlChannel::process(uint32_t now_us) {
  for (int i = 0; i < 3; ++i) {
    const uint8_t bit = kButtons[i];
    if ((clicked_ & bit) && time_reached(now_us, release_at_us_[i])) {
      clicked_ = static_cast<uint8_t>(clicked_ & ~bit);
      buttons_ = static_cast<uint8_t>(buttons_ & ~bit);
    }
  }
}

}  // namespace node
}  // namespace mb2co
