// What one latency window of the lab holds besides the press itself: the CAN
// frames a station can take in while the lab's operator works. The lab's
// bound (lab_bound.h, docs/timing.md §9 "Frames on the path") counts those
// that can reach the passes the path waits for, instead of a full receive
// buffer in every pass. Internal to hil/sim.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

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

/// Passes of the path on one Arduino that follow one another (each the
/// next pass after the one before it): their frames were all received in
/// one interval of at most `span_ns` (a pass takes in what came since the
/// previous pass emptied the receive buffers).
struct PathCluster {
  uint32_t passes = 0;
  SimNs span_ns = 0;
};

/// How late a message `id` can be received after the event that sends it:
/// the step to the end of the pass that queues it plus its response time.
struct MessageLateness {
  uint32_t id = 0;
  SimNs late_ns = 0;
};

/// Upper bound on the CAN frames station `x` takes in by the passes of the
/// path (`clusters`; docs/timing.md §9, "Frames on the path"): a frame
/// costs a pass only if that pass is one the path waits for, a pass takes
/// at most can_rx_buffers, and a message's sends reach a cluster only as
/// often as its rate allows in the cluster's interval and in the window
/// (`window_ns`), each message released up to `jitter_ns` late (in a
/// cluster's interval: its own lateness from `late` where listed). The rate
/// of a message is what the message set allows (its inhibit time, the
/// SYNC period, the heartbeat period, the application's minimum
/// inter-arrival), and for the event TPDOs of the lab line the sends the
/// operator `op` can cause in one window plus the event timer's.
/// `button_station` is the station of the lab button. The result is the
/// largest assignment of sends to passes (a maximum flow). Fails when a
/// message has no known rate.
Status frames_on_path(Line& line, int x, int button_station, SimNs window_ns, SimNs jitter_ns,
                      const std::vector<MessageLateness>& late, const LabOperator& op,
                      const std::vector<PathCluster>& clusters, uint32_t* frames);

}  // namespace sim
}  // namespace mb2co
