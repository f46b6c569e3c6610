#include "timing/line_latency.h"

#include "timing/time_base.h"

namespace mb2co {
namespace timing {
namespace {

bool hop(const LineScratch& s, size_t count, uint8_t node, uint32_t bitrate, uint64_t* best_ns,
         uint64_t* worst_ns) {
  for (size_t i = 0; i < count; ++i) {
    const MessageSpec& m = s.specs[i];
    if (m.extended || m.id != kTpdo1CobBase + node) continue;
    if (s.results[i].revised != Bound::kBounded) return false;
    *best_ns = can_hop_best_ns(false, m.dlc, bitrate);
    *worst_ns = ticks_to_ns_ceil(s.results[i].r, bitrate);
    return true;
  }
  return false;
}

}  // namespace

HopStatus fill_can_hops(const LineCanConfig& cfg, WorstCase convention, uint8_t button_node, uint8_t pc_node,
                        const LineScratch& scratch, LatencyParams* p, LineStatus* line_status) {
  size_t count = 0;
  *line_status = build_line_messages(cfg, scratch.specs, scratch.capacity, &count);
  if (*line_status != LineStatus::kOk) return HopStatus::kLine;
  if (!cfg.tpdo1) return HopStatus::kNoTpdo1;
  if (button_node == 0 || pc_node == 0 || button_node > cfg.stations || pc_node > cfg.stations ||
      button_node == pc_node) {
    return HopStatus::kNode;
  }
  size_t bad = 0;
  // A valid line configuration always yields valid analysis input.
  (void)analyse_set(scratch.specs, count, cfg.bitrate_bps, convention, scratch.rta, scratch.results, &bad);
  if (!hop(scratch, count, button_node, cfg.bitrate_bps, &p->can_up_best_ns, &p->can_up_worst_ns) ||
      !hop(scratch, count, pc_node, cfg.bitrate_bps, &p->can_down_best_ns, &p->can_down_worst_ns)) {
    return HopStatus::kUnbounded;
  }
  return HopStatus::kOk;
}

}  // namespace timing
}  // namespace mb2co
