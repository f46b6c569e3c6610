// Replays the worst case that the revised analysis assumes for one message:
// who holds the bus when, from the critical instant to the end of the
// level-i busy period. Feeds the SVG of `mb2co-timing rta --svg` and lets
// tests check the analysis against an independent step-by-step schedule.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "timing/rta.h"

namespace mb2co {
namespace timing {

/// One transmission on the bus, in the caller's time unit.
struct BusSegment {
  size_t message;     ///< index into the set (the blocker is a lower priority)
  uint64_t instance;  ///< which instance of that message (0 = first)
  uint64_t start;
  uint64_t end;  ///< start + C of that message
};

/// Arrival (queuing) time of instance n of message m in the worst case:
/// instance 0 queued at 0 after the maximum jitter, later ones as early as
/// possible, n T - J (never before 0).
uint64_t worst_case_arrival(const RtaMessage& m, uint64_t n);

/// Writes the schedule of the level-i busy period into out[0..capacity):
/// the longest lower-priority frame starts at 0 (if any), every message of
/// priority i or higher arrives per worst_case_arrival, and whenever the bus
/// falls free the highest-priority message queued before free + τ_bit wins
/// (as in eq. 6.10). Stops at the end of the busy period (everything queued
/// before now is sent: the L of eq. 6.7), at kMaxBusyPeriod, or when out is full
/// (then *truncated = true). Returns the number of segments written.
/// `sent` is caller-owned scratch of i + 1 counters (instances sent so far).
size_t trace_busy_period(const RtaMessage* set, size_t count, size_t i, uint64_t tau_bit, uint64_t* sent,
                         BusSegment* out, size_t capacity, bool* truncated);

}  // namespace timing
}  // namespace mb2co
