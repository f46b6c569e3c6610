#include "sim/can_trace.h"

#include "host/candump_text.h"

namespace mb2co {
namespace sim {

void CanTrace::start_run() {
  if (frames_ != 0) offset_ns_ = last_ns_ + kNsPerS;
}

void CanTrace::frame(SimNs t, const CanFrame& f) {
  last_ns_ = offset_ns_ + t;
  text_ += candump_log_line(last_ns_ / kNsPerUs, iface_, f);
  ++frames_;
}

}  // namespace sim
}  // namespace mb2co
