// Acceptance masks and filters of the MCP2515 computed from what a device
// must receive: its acceptance ranges (platform/device_port.h, CanIdRange)
// as the standard ids they admit (admitted_ids), then a plan for those ids.
// Pure computation, no chip access; no CANopen in here.
//
// The chip has RXB0 with mask RXM0 and filters RXF0..RXF1, and RXB1 with mask
// RXM1 and filters RXF2..RXF5. A frame is accepted when, for some filter F of
// a buffer with mask M, (id & M) == (F & M). RXB0 rolls over into RXB1, so
// RXB1's own filters never get both ids of a pair that may arrive back to
// back (kBackToBackBits). With at most 6 ids, no two of them such a pair,
// every id gets its own filter and the masks stay exact; otherwise ids
// sharing a buffer are merged by clearing mask bits, which also lets some
// unsubscribed ids through (FilterPlan::exact is false then and
// accepted_ids says how many pass).
#pragma once
#include <stdint.h>

#include "platform/device_port.h"  // CanIdRange

namespace mb2co {
namespace mcp2515 {

/// Most ids a plan takes. The search tries every run of sorted ids for RXB0
/// and a greedy mask search for each buffer: time grows steeply with the
/// count. Measured on the ATmega328P at 16 MHz (simavr, cycle count; lines
/// filter_plan_* of firmware/avr/measure-pass-time.sh), the whole plan:
/// 6 ids 3.9 ms, 9 ids (a gateway in a ring) 23 ms, 12 ids 80 ms. In a loop
/// that must keep going, plan with FilterPlanner (at most ~1 ms a step).
constexpr uint8_t kMaxSubscribedIds = 12;
constexpr uint16_t kMaxStandardId = 0x7FF;
/// Ids equal in these bits may reach the bus back to back: the node id
/// (bits 6..0 in CANopen's pre-defined connection set) and bit 8, in which a
/// node's TPDO1 (180h + n) and heartbeat (700h + n) agree, the two frames
/// its timers send in one pass every period (station defaults: both
/// 100 ms); so do NMT (000h) and SYNC (080h), a master's. The chip holds two
/// such frames only if the first lands in RXB0, which rolls over into RXB1,
/// or they land in different buffers: a plan never leaves both to RXB1's own
/// filters. A node's other PDOs (280h, 380h, 480h + n, sent on events) and
/// an SDO request (600h + n) differ in bit 8 from its heartbeat: RXB1 may
/// take one of them beside it, which keeps the plans as tight as before
/// (node 1 of the station's default ring of 4: 24 ids pass, not 16; with
/// the node id alone as the pair's bits, 35).
constexpr uint16_t kBackToBackBits = 0x17F;

struct FilterPlan {
  uint16_t mask[2];       ///< RXM0 (RXB0), RXM1 (RXB1): 11-bit standard-id masks
  uint16_t filter[6];     ///< RXF0..RXF5: RXF0-1 use mask[0], RXF2-5 mask[1]
  bool exact;             ///< true when exactly the subscribed ids pass
  uint16_t accepted_ids;  ///< how many of the 2048 standard ids pass (>= distinct ids given)
  // Invariant: the given ids RXB0's filters miss differ in kBackToBackBits.
};

/// The plan search in bounded steps, so that a main loop keeps serving its
/// peers while it plans: start(), then step() once per loop pass until it
/// returns true, then plan(). The result is the one plan_filters gives.
///
/// All zero (value-initialised) it is idle. No heap; 26 B on the AVR: it
/// keeps a pointer to the caller's id list, not a copy.
class FilterPlanner {
 public:
  /// Comparisons of masked ids one step() does before it stops (it finishes
  /// the candidate merge in progress: at most 66 more). The longest step,
  /// the last one (it also builds the plan) included, takes 0.70 ms for 9
  /// ids, 0.88 ms for 12 on the ATmega328P at 16 MHz (44 and 149 steps).
  static const uint16_t kStepWork = 270;

  /// Begins a plan for ids[0..count) as admitted_ids gives them: strictly
  /// ascending (sorted, no duplicates), each <= kMaxStandardId, 1 <= count
  /// <= kMaxSubscribedIds (not checked: the lists come from admitted_ids or
  /// plan_filters). The planner reads ids[] at every step: they must stay
  /// valid and unchanged until step() returned true or stop().
  void start(const uint16_t* ids, uint8_t count);
  /// Does a bounded piece of the search (kStepWork). True when no work is
  /// left: done() (a plan is ready) or idle.
  bool step();
  /// Back to idle; a plan in progress is dropped.
  void stop() { phase_ = kIdle; }
  bool busy() const { return phase_ == kRun || phase_ == kRest; }
  bool done() const { return phase_ == kDone; }
  /// The plan, when done(): masks, filters, exact, accepted_ids.
  void plan(FilterPlan& out) const;

 private:
  enum Phase : uint8_t {
    kIdle = 0,  ///< zero: a value-initialised planner is idle
    kRun,       ///< mask search for RXB0's run ids_[a_, b_)
    kRest,      ///< mask search for RXB1's ids (the others)
    kDone,
  };
  uint8_t distinct(uint8_t a, uint8_t b, bool run, uint16_t mask, uint16_t* out, uint8_t filters) const;
  void begin_round(uint16_t mask);
  void finish_group(uint8_t values, uint16_t* scratch);  ///< scratch: room for kMaxSubscribedIds
  void consider(uint16_t cost, uint16_t mask1);
  bool loses(uint16_t cost) const;
  void next_split();

  // A group search works on the group's ids (RXB0: ids_[a_, b_); RXB1: the
  // others), one per distinct value under mask_ (distinct() finds them at
  // each step), and evaluates merging values i_ and j_ (j_ < i_).
  const uint16_t* ids_;
  uint8_t n_;
  Phase phase_;
  uint8_t a_, b_;            ///< current split: RXB0 takes ids_[a_, b_)
  uint8_t i_, j_;            ///< next candidate pair of the current round
  uint8_t best_a_, best_b_;  ///< best split so far
  uint16_t mask_;            ///< the group's mask so far
  uint16_t round_mask_;      ///< best merge of this round (valid after its first pair)
  uint16_t round_cost_;      ///< ids that merge lets through; 0xFFFF: none yet
  uint16_t m0_, cost0_;      ///< RXB0's mask and accepted ids for the current split
  uint16_t best_cost_;       ///< accepted ids of the best split; 0xFFFF: none yet
  uint16_t best_m0_, best_m1_;
};

/// The standard ids ranges[0..count) admit, sorted ascending without
/// duplicates, into ids[0..n) (room for kMaxSubscribedIds); returns n. The
/// remote bit of a range is no id bit (the chip filters data and remote
/// frames alike: a superset). 0 (no plan: the filters stay open, a
/// superset) when a range admits more than one id (a network gateway's
/// 580h-5FFh; planning for wider ranges would cost the station's flash and
/// no image needs it), when the ids are more than kMaxSubscribedIds, or when
/// there are none.
uint8_t admitted_ids(const CanIdRange* ranges, uint8_t count, uint16_t* ids);

/// Computes a plan accepting at least every id in ids[0..count) in one go
/// (FilterPlanner to the end). Duplicates are allowed. Returns false (plan
/// untouched) when count is 0 or above kMaxSubscribedIds, or an id exceeds
/// kMaxStandardId.
bool plan_filters(const uint16_t* ids, uint8_t count, FilterPlan& plan);

/// True when standard id `id` passes the plan (the chip's acceptance rule).
bool plan_accepts(const FilterPlan& plan, uint16_t id);

}  // namespace mcp2515
}  // namespace mb2co
