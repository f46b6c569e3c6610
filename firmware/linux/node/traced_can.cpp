#include "traced_can.h"

#include <time.h>

namespace mb2co {
namespace node {

const CanControl TracedCan::kControl = {nullptr, &TracedCan::set_filters_of};

bool TracedCan::send_to(void* ctx, const CanFrame& frame) {
  TracedCan& self = *static_cast<TracedCan*>(ctx);
  // Queued for the loop's flush; a frame the port refused is not in the trace.
  if (!self.port_.queue(frame)) return false;
  self.log_.write(realtime_us(), frame);
  return true;
}

void TracedCan::set_filters_of(void* ctx, const CanIdRange* ranges, uint8_t count) {
  linux_port::SocketCanPort::kControl.set_filters(&static_cast<TracedCan*>(ctx)->port_, ranges, count);
}

uint64_t TracedCan::realtime_us() {
  timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

}  // namespace node
}  // namespace mb2co
