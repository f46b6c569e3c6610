// The one clock the bus loop's services see. Two sources feed it: the
// monotonic clock, read once per pass, and each frame's kernel receive time,
// which the SocketCAN port shifts from the wall clock with two separate
// clock reads (socketcan_port.h). The shift can put a frame a little before
// a pass time handed out earlier (the second clock read comes later, the
// wall clock slews): a transfer started at the pass then "ends" before it
// starts, and its duration wrapped to 4294.967 s (issue 22 item 5). The
// services get the time never earlier than one they had before: a frame
// that cannot have come before the pass that sent its request gets that
// pass's time.
#pragma once
#include <stdint.h>

#include "canopen/clock.h"

namespace mb2co {
namespace master {

class ServiceClock {
 public:
  /// `us` (wrapping µs), or the latest time handed out when `us` is
  /// earlier than that one.
  uint32_t at(uint32_t us) {
    if (!started_ || time_reached(us, last_us_)) last_us_ = us;
    started_ = true;
    return last_us_;
  }

 private:
  uint32_t last_us_ = 0;
  bool started_ = false;
};

}  // namespace master
}  // namespace mb2co
