#include "sim/node_timing.h"

namespace mb2co {
namespace sim {

NodeTiming uno_timing() {
  return NodeTiming();
}

NodeTiming fast_timing() {
  NodeTiming t;
  t.loop_ns = 1000 * kNsPerUs;
  t.pass_ns = 100 * kNsPerUs;
  t.jitter_ns = 200 * kNsPerUs;
  t.frame_ns = t.byte_ns = t.request_ns = t.write_ns = t.item_ns = t.item_address_ns = 0;
  return t;
}

SimNs request_cost(const NodeTiming& t, const uint8_t* req, size_t len) {
  if (len < 6) return t.request_ns;
  const uint8_t fc = req[1];
  const uint32_t start = (uint32_t{req[2]} << 8) | req[3];
  uint32_t count = (uint32_t{req[4]} << 8) | req[5];
  const bool single_write = fc == 0x05 || fc == 0x06;
  if (single_write) count = 1;
  if (fc > 0x06 && fc != 0x0F && fc != 0x10) return t.request_ns;
  if (count > 2000) count = 2000;
  const SimNs per_item = t.item_ns + (fc >= 0x05 ? t.write_ns : 0);
  return t.request_ns + per_item * count + t.item_address_ns * start;
}

SimNs max_pass_ns(const NodeTiming& t, size_t frames, size_t bytes, SimNs request) {
  return t.pass_ns + t.jitter_ns + t.frame_ns * frames + t.byte_ns * bytes + request;
}

}  // namespace sim
}  // namespace mb2co
