#include "control_channel.h"

#include <sstream>

#include "canopen/clock.h"
#include "host/panel_command.h"

namespace mb2co {
namespace node {

namespace {

const uint8_t kButtons[3] = {gateway::kStart, gateway::kStop, gateway::kStop2};

std::string stamped(const std::string& text, uint32_t now_us) {
  return text + " at_us=" + std::to_string(now_us);
}

}  // namespace

std::string ControlChannel::leds_text(uint8_t leds) {
  // A neighbour's LED blinks while that neighbour is unknown: "blink", so
  // the line changes when the status does, not at every toggle (4 a second).
  canopen::ObjectDictionary& od = gw_.od();
  namespace e = gateway::od::GatewayEntry;
  auto led = [&](canopen::OdKey status, uint8_t bit) -> const char* {
    if (od.get(od.find(status)) == gateway::kNeighbourUnknown) return "blink";
    return (leds & bit) ? "1" : "0";
  };
  std::ostringstream s;
  s << "leds self=" << ((leds & gateway::kLedRunSelf) ? 1 : 0)
    << " prev=" << led(e::x2110_3_prevStatus, gateway::kLedRunPrev)
    << " next=" << led(e::x2120_3_nextStatus, gateway::kLedRunNext)
    << " lab=" << ((leds & gateway::kLedLab) ? 1 : 0);
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
  const PanelCommand c = parse_panel_command(line);
  if (c.kind == PanelCommand::kBlank) return std::string();
  if (c.kind == PanelCommand::kError) return "error " + c.error;
  if (c.kind == PanelCommand::kOther) {
    if (!c.rest.empty()) return "error unexpected '" + c.rest + "'";
    if (c.word == "leds?") {
      const canopen::ObjectDictionary& od = gw_.od();
      return stamped(
          leds_text(static_cast<uint8_t>(od.get(od.find(gateway::od::GatewayEntry::x2200_0_leds)))), now_us);
    }
    if (c.word == "state?") return stamped(state_text(), now_us);
    if (c.word == "counters?") return counters_text();
    if (c.word == "help") {
      return std::string(panel_help_lines()) +
             "\nhelp leds? | state? | counters? | quit | help   (docs/mb2co-node.md)";
    }
    if (c.word == "quit") {
      quit_ = true;
      return "bye";
    }
    return "error unknown command '" + c.word + "' (help lists them)";
  }
  const uint8_t bit = kButtons[c.button];
  if (c.action == PanelCommand::kRelease) {
    buttons_ = static_cast<uint8_t>(buttons_ & ~bit);
    clicked_ = static_cast<uint8_t>(clicked_ & ~bit);
    return "ok";
  }
  if (c.action == PanelCommand::kClick) {
    clicked_ = static_cast<uint8_t>(clicked_ | bit);
    release_at_us_[c.button] = now_us + c.hold_ms * 1000u;
  } else {
    clicked_ = static_cast<uint8_t>(clicked_ & ~bit);
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

void ControlChannel::next_deadline(NextDeadline& d) const {
  for (int i = 0; i < 3; ++i) {
    if (clicked_ & kButtons[i]) d.at(release_at_us_[i]);
  }
}

}  // namespace node
}  // namespace mb2co
