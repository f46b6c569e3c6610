#include "timing/bus_trace.h"

namespace mb2co {
namespace timing {

uint64_t worst_case_arrival(const RtaMessage& m, uint64_t n) {
  if (n == 0) return 0;
  const uint64_t nominal = n * m.t;
  return nominal > m.j ? nominal - m.j : 0;
}

size_t trace_busy_period(const RtaMessage* set, size_t count, size_t i, uint64_t tau_bit, uint64_t* sent,
                         BusSegment* out, size_t capacity, bool* truncated) {
  *truncated = false;
  size_t written = 0;
  uint64_t now = 0;
  for (size_t k = 0; k <= i; ++k) sent[k] = 0;

  // The blocker: the longest lower-priority frame (the first of equals).
  size_t blocker = count;
  for (size_t k = i + 1; k < count; ++k) {
    if (blocker == count || set[k].c > set[blocker].c) blocker = k;
  }
  if (blocker != count) {
    if (capacity == 0) {
      *truncated = true;
      return 0;
    }
    out[written++] = BusSegment{blocker, 0, 0, set[blocker].c};
    now = set[blocker].c;
  }

  while (now <= kMaxBusyPeriod) {
    // The busy period ends when everything queued before `now` is sent
    // (an arrival exactly at the end opens the next one, as in eq. 6.7).
    bool pending = false;
    for (size_t k = 0; k <= i && !pending; ++k) {
      pending = worst_case_arrival(set[k], sent[k]) < now;
    }
    if (!pending && now > 0) break;
    // Arbitration: the lowest index queued before now + τ_bit wins.
    size_t winner = i + 1;
    for (size_t k = 0; k <= i; ++k) {
      if (worst_case_arrival(set[k], sent[k]) < now + tau_bit) {
        winner = k;
        break;
      }
    }
    if (winner > i) break;
    if (written == capacity) {
      *truncated = true;
      break;
    }
    out[written++] = BusSegment{winner, sent[winner], now, now + set[winner].c};
    ++sent[winner];
    now += set[winner].c;
  }
  return written;
}

}  // namespace timing
}  // namespace mb2co
