// The simulated bus as a `candump -L` log: one line per frame delivered
// (error frames are not frames), stamped with the simulated time, so
// canplayer can replay a run onto a real or virtual bus and Wireshark,
// SavvyCAN or candump users can open it. A lab run holds several simulated
// runs that each start at t = 0: each continues 1 s after the previous one's
// last frame, so the log's time only moves forward.
#pragma once
#include <string>

#include "canopen/can_frame.h"
#include "sim/event_queue.h"

namespace mb2co {
namespace sim {

class CanTrace {
 public:
  /// `iface`: the interface name written on every line (canplayer maps it:
  /// `canplayer vcan0=can0 -I FILE`).
  explicit CanTrace(std::string iface = "can0") : iface_(std::move(iface)) {}
  /// A new simulated run begins (its clock starts again at 0).
  void start_run();
  /// A frame delivered at simulated time t of the current run.
  void frame(SimNs t, const CanFrame& f);
  const std::string& text() const { return text_; }
  uint64_t frames() const { return frames_; }

 private:
  std::string iface_;
  std::string text_;
  SimNs offset_ns_ = 0;  ///< start of the current run on the log's time line
  SimNs last_ns_ = 0;    ///< the log's last time stamp
  uint64_t frames_ = 0;
};

}  // namespace sim
}  // namespace mb2co
