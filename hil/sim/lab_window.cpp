#include "sim/lab_window.h"

#include "sim/lab_bound.h"
#include "sim/lab_hops.h"

namespace mb2co {
namespace sim {
namespace {

uint32_t od_get(canopen::ObjectDictionary& od, uint16_t index, uint8_t sub) {
  return od.get(od.find(index, sub));
}

/// Releases at least `period_ns` apart that fit in a closed window of
/// `span_ns` (the window plus how late one may be received).
uint32_t releases(SimNs span_ns, SimNs period_ns) {
  return static_cast<uint32_t>(span_ns / period_ns + 1);
}

/// Sends of event TPDO `n` of station `s` the operator can cause in one
/// window (its mapped objects changing), or -1 when it maps something the
/// lab does not account for.
int operator_sends(Line& line, int s, uint16_t n, int button_station, const LabOperator& op) {
  canopen::ObjectDictionary& od = line.node(s).gateway().od();
  const uint16_t map = static_cast<uint16_t>(0x1A00 + n);
  const uint32_t count = od_get(od, map, 0);
  const uint32_t first = od_get(od, map, 1) >> 16;
  const int others = op.interference ? 2 : 0;  // STOP2 with the press, STOP before the LED
  if (count == 1 && first == 0x6000) return (s == button_station ? 1 : 0) + others;  // debounced buttons
  if (count == 1 && first == 0x6200) return 1;  // the lab LED: on once per press
  // The line state (RUN state, STOP2 counter): with RUN fixed it changes
  // only when a STOP2 press here is counted.
  if (line_state_tpdo_fixed(line, s, n)) return op.interference ? 1 : 0;
  return -1;
}

}  // namespace

Status frames_in_window(Line& line, int x, int button_station, SimNs window_ns, SimNs jitter_ns,
                        const LabOperator& op, uint32_t* frames) {
  const LineConfig& c = line.config();
  const CanController& rx = line.node(x).can();
  const SimNs span = window_ns + jitter_ns;
  uint32_t total = 0;
  uint32_t sync_period_us = 0;
  for (int s = 0; s < line.size(); ++s) {
    canopen::ObjectDictionary& od = line.node(s).gateway().od();
    const uint32_t sync_cob = od_get(od, 0x1005, 0);
    if ((sync_cob & 0x40000000u) && od_get(od, 0x1006, 0) != 0) {
      sync_period_us = od_get(od, 0x1006, 0);
      if (s != x && rx.accepts(static_cast<uint16_t>(sync_cob & 0x7FFu)))
        total += releases(span, SimNs{sync_period_us} * kNsPerUs);
    }
  }
  for (int s = 0; s < line.size(); ++s) {
    if (s == x) continue;  // a controller does not receive its own frames
    canopen::ObjectDictionary& od = line.node(s).gateway().od();
    for (uint16_t n = 0; n < 4; ++n) {
      const uint16_t comm = static_cast<uint16_t>(0x1800 + n);
      const uint32_t cob = od_get(od, comm, 1);
      if ((cob & 0x80000000u) || od_get(od, static_cast<uint16_t>(0x1A00 + n), 0) == 0) continue;
      if (!rx.accepts(static_cast<uint16_t>(cob & 0x7FFu))) continue;
      const uint32_t type = od_get(od, comm, 2);
      const uint32_t inhibit_us = od_get(od, comm, 3) * 100u;
      uint32_t period_us = 0;  // what the message set allows
      if (type <= 240) {
        period_us = sync_period_us * (type == 0 ? 1u : type);
      } else {
        period_us = inhibit_us != 0
                        ? inhibit_us
                        : application_interarrival_us(c, od_get(od, static_cast<uint16_t>(0x1A00 + n), 1));
      }
      if (period_us == 0) {
        if (type <= 240) continue;  // synchronous without a SYNC producer: never sent
        return Status::failure(
            strf("TPDO%u of node %d has neither an inhibit time nor a known event rate", n + 1, s + 1));
      }
      uint32_t sends = releases(span, SimNs{period_us} * kNsPerUs);
      const int caused = type >= 254 ? operator_sends(line, s, n, button_station, op) : -1;
      if (caused >= 0) {
        // Plus the event timer's: it restarts at every send (CiA 301), so
        // its sends are an event time apart at least.
        const uint32_t event_ms = od_get(od, comm, 5);
        const uint32_t timer = event_ms != 0 ? releases(span, SimNs{event_ms} * kNsPerMs) : 0;
        const uint32_t operated = static_cast<uint32_t>(caused) + timer;
        if (operated < sends) sends = operated;
      }
      total += sends;
    }
    const uint32_t hb_ms = od_get(od, 0x1017, 0);
    if (hb_ms != 0 && rx.accepts(static_cast<uint16_t>(0x700 + s + 1)))
      total += releases(span, SimNs{hb_ms} * kNsPerMs);
  }
  *frames = total;
  return Status::ok();
}

}  // namespace sim
}  // namespace mb2co
