// What one latency window of the lab holds besides the press itself: the CAN
// frames a station can take in while the lab's operator works. The lab's
// bound (lab_bound.h, docs/timing.md §9 "The bound per kind of pass") counts
// them once for the whole window instead of a full receive buffer in every
// pass. Internal to hil/sim.
#pragma once
#include <stdint.h>

#include <string>

#include "host/status.h"
#include "sim/line.h"

namespace mb2co {
namespace sim {

/// What the lab's operator does in one latency window besides pressing the
/// lab button (START on the button's station). Presses are at least 20 ms
/// apart from the previous press's release being seen (press_loop.cpp;
/// worst_presses.cpp waits 150 ms), so one window holds one press.
struct LabOperator {
  /// The --worst search of the Modbus + CANopen path: STOP2 on every
  /// station with the press, STOP on every station once more before the
  /// LED, both released after the LED is on.
  bool interference = false;
};

/// Upper bound on the CAN frames station `x` takes in during any window of
/// `window_ns` (its filters admit them, another station sends them), each
/// message released up to `jitter_ns` late: per message, the rate the
/// message set allows (its inhibit time, the SYNC period, the heartbeat
/// period, the application's minimum inter-arrival), and for the event
/// TPDOs of the lab line the sends the operator `op` can cause in one
/// window plus the event timer's (docs/timing.md §9). `button_station` is
/// the station of the lab button. Fails when a message has no known rate.
Status frames_in_window(Line& line, int x, int button_station, SimNs window_ns, SimNs jitter_ns,
                        const LabOperator& op, uint32_t* frames);

}  // namespace sim
}  // namespace mb2co
