// Acceptance masks and filters of the MCP2515 computed from the list of
// standard CAN ids a node subscribes to. Pure computation, no chip access.
//
// The chip has RXB0 with mask RXM0 and filters RXF0..RXF1, and RXB1 with mask
// RXM1 and filters RXF2..RXF5. A frame is accepted when, for some filter F of
// a buffer with mask M, (id & M) == (F & M). With at most 6 ids every id gets
// its own filter and the masks stay exact; with more, ids sharing a buffer are
// merged by clearing mask bits, which also lets some unsubscribed ids through
// (FilterPlan::exact is false then and accepted_ids says how many pass).
#pragma once
#include <stdint.h>

namespace mb2co {
namespace mcp2515 {

/// Most ids plan_filters takes. It tries every run of sorted ids for RXB0 and
/// a greedy mask search for each buffer: time grows steeply with the count.
/// Measured on the ATmega328P at 16 MHz (simavr, cycle count; lines
/// filter_plan_ids_* of firmware/avr/measure-pass-time.sh): 6 ids 30 ms,
/// 9 ids (a gateway in a ring) 102 ms, 12 ids 369 ms. Plan at start-up, not
/// in the middle of Modbus traffic. Stack: ~100 bytes.
constexpr uint8_t kMaxSubscribedIds = 12;
constexpr uint16_t kMaxStandardId = 0x7FF;

struct FilterPlan {
  uint16_t mask[2];    ///< RXM0 (RXB0), RXM1 (RXB1): 11-bit standard-id masks
  uint16_t filter[6];  ///< RXF0..RXF5: RXF0-1 use mask[0], RXF2-5 mask[1]
  bool exact;          ///< true when exactly the subscribed ids pass
  uint16_t accepted_ids;  ///< how many of the 2048 standard ids pass (>= distinct ids given)
};

/// Computes a plan accepting at least every id in ids[0..count). Duplicates
/// are allowed. Returns false (plan untouched) when count is 0 or above
/// kMaxSubscribedIds, or an id exceeds kMaxStandardId.
/// Out of line: inlined into its caller's loop, its arrays would enlarge
/// that frame beyond what the AVR reaches with short offsets (-200 B on
/// the Uno).
__attribute__((noinline)) bool plan_filters(const uint16_t* ids, uint8_t count, FilterPlan& plan);

/// True when standard id `id` passes the plan (the chip's acceptance rule).
bool plan_accepts(const FilterPlan& plan, uint16_t id);

}  // namespace mcp2515
}  // namespace mb2co
