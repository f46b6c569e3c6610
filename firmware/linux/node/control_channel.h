// The test/bench control channel of mb2co-node: one command per line on
// stdin; replies and events on stdout, one line each (docs/mb2co-node.md).
// Command words and button names in any letter case.
//   press B | release B | click B [ms]   (B: START, STOP, STOP2) -> "ok"
//   leds?     -> "leds self=1 prev=0 next=1 lab=0 at_us=T" (prev/next "blink"
//                while that neighbour is unknown: its LED blinks at 2 Hz)
//   state?    -> "state node=1 nmt=5 run=1 cause=0 stop2=0 prev=3:1:1 next=2:1:1 at_us=T"
//                (prev/next: node id : status 0 unknown, 1 alive, 2 none : RUN state)
//   counters? -> "counters bus=N comm=N exc=N srv=N noresp=N ovr=N" (Modbus 08/0B..0F, 12)
//   help      -> the commands, lines starting "help "
//   quit      -> "bye", then the node exits
// Events: a "leds ..." line whenever that text changes and a "state ..."
// line whenever the state changes, both stamped with the node's own clock
// (at_us: CLOCK_MONOTONIC in µs, truncated to 32 bits) at the loop pass that
// saw the change. Unknown input gets "error <reason>".
#pragma once
#include <stdint.h>

#include <string>

#include "canopen/clock.h"
#include "gateway/gateway.h"

namespace mb2co {
namespace node {

class ControlChannel {
 public:
  explicit ControlChannel(gateway::Gateway& gw) : gw_(gw) {}
  /// Handles one line; returns the reply (without newline), "" for a blank line.
  std::string handle(const std::string& line, uint32_t now_us);
  /// Releases clicked buttons whose time is up.
  void process(uint32_t now_us);
  /// Adds the release times of clicked buttons to `d` (process() due then).
  void next_deadline(NextDeadline& d) const;
  /// Event lines (each ending in '\n') for what changed since the last call,
  /// given the LED levels the gateway drives now; "" when nothing changed.
  std::string events(uint8_t leds, uint32_t now_us);
  uint8_t buttons() const { return buttons_; }
  bool quit() const { return quit_; }

 private:
  std::string leds_text(uint8_t leds);
  std::string state_text();
  std::string counters_text();

  gateway::Gateway& gw_;
  uint8_t buttons_ = 0;
  uint8_t clicked_ = 0;                    ///< buttons that click will release
  uint32_t release_at_us_[3] = {0, 0, 0};  ///< per button bit index
  bool quit_ = false;
  std::string leds_shown_;  ///< last leds/state event printed (without time)
  std::string state_shown_;
};

}  // namespace node
}  // namespace mb2co
