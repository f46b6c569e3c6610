#include "timing/rta.h"

#include "timing/utilisation.h"

namespace mb2co {
namespace timing {
namespace {

uint64_t ceil_div(uint64_t a, uint64_t b) {
  return a / b + (a % b != 0 ? 1u : 0u);
}

// Σ_{k < count} ceil((x + J_k + extra)/T_k) C_k. With x < kMaxBusyPeriod and the
// utilisation of these messages below 1 the sum stays below x + Σ C_k, far
// from overflow (inputs ≤ 2^52).
uint64_t demand(const RtaMessage* set, size_t count, uint64_t x, uint64_t extra) {
  uint64_t sum = 0;
  for (size_t k = 0; k < count; ++k) {
    sum += ceil_div(x + set[k].j + extra, set[k].t) * set[k].c;
  }
  return sum;
}

uint64_t sum_c(const RtaMessage* set, size_t count) {
  uint64_t sum = 0;
  for (size_t k = 0; k < count; ++k) sum += set[k].c;
  return sum;
}

bool message_valid(const RtaMessage& m) {
  return m.c != 0 && m.t != 0 && m.d != 0 && m.c <= kMaxValue && m.t <= kMaxValue && m.d <= kMaxValue &&
         m.j <= kMaxValue;
}

// Revised analysis of message i whose level utilisation is below 1. `w0`:
// the queuing delay of instance 0, already solved by the first attempt.
void revised(const RtaMessage* set, size_t i, uint64_t tau_bit, uint64_t w0, RtaResult& out) {
  const RtaMessage& m = set[i];
  out.busy = busy_period(set, i, out.blocking, &out.revised);
  if (out.revised != Bound::kBounded) return;
  out.instances = ceil_div(out.busy + m.j, m.t);
  if (out.instances > kMaxInstances) {
    out.revised = Bound::kHorizon;
    return;
  }
  uint64_t w = w0;
  for (uint64_t q = 0; q < out.instances; ++q) {
    if (q > 0) {
      // eq. 6.11: start from the previous instance
      w = queuing_delay(set, i, tau_bit, out.blocking, q, w + m.c, &out.revised);
      if (out.revised != Bound::kBounded) return;
    }
    // eq. 6.13 with jitter: R_q = J + w + C - q T (instance q is queued at
    // q T - J at the earliest; an instance that would finish before it is
    // queued cannot be the worst and is skipped).
    const uint64_t finish = m.j + w + m.c;
    const uint64_t release = q * m.t;
    if (finish > release && finish - release > out.r) {
      out.r = finish - release;
      out.critical_instance = q;
    }
  }
}

}  // namespace

uint64_t blocking_time(const RtaMessage* set, size_t count, size_t i) {
  uint64_t b = 0;
  for (size_t k = i + 1; k < count; ++k) {
    if (set[k].c > b) b = set[k].c;
  }
  return b;
}

uint64_t busy_period(const RtaMessage* set, size_t i, uint64_t blocking, Bound* outcome) {
  uint64_t l = blocking + sum_c(set, i + 1);
  for (;;) {
    if (l > kMaxBusyPeriod) {
      *outcome = Bound::kHorizon;
      return l;
    }
    const uint64_t next = blocking + demand(set, i + 1, l, 0);
    if (next == l) break;
    l = next;
  }
  *outcome = Bound::kBounded;
  return l;
}

uint64_t queuing_delay(const RtaMessage* set, size_t i, uint64_t tau_bit, uint64_t blocking, uint64_t q,
                       uint64_t w_start, Bound* outcome) {
  const uint64_t own = blocking + q * set[i].c;
  uint64_t w = w_start;
  for (;;) {
    if (w > kMaxBusyPeriod) {
      *outcome = Bound::kHorizon;
      return w;
    }
    const uint64_t next = own + demand(set, i, w, tau_bit);
    if (next == w) break;
    w = next;
  }
  *outcome = Bound::kBounded;
  return w;
}

RtaStatus analyse(const RtaMessage* set, size_t count, uint64_t tau_bit, RtaResult* results,
                  size_t* bad_index) {
  for (size_t i = 0; i < count; ++i) {
    if (!message_valid(set[i]) || tau_bit == 0 || tau_bit > kMaxValue) {
      *bad_index = i;
      return RtaStatus::kBadMessage;
    }
  }
  // Top-down: level-i utilisation decides whether the busy period of i ends
  // (revised) and whether the higher-priority interference is bounded (first).
  Utilisation level;
  bool hp_bounded = true;
  for (size_t i = 0; i < count; ++i) {
    RtaResult& out = results[i];
    out = RtaResult{};
    out.first = hp_bounded ? Bound::kBounded : Bound::kUtilisation;
    level.add(set[i].c, set[i].t);
    hp_bounded = level.below_one();
    out.revised = hp_bounded ? Bound::kBounded : Bound::kUtilisation;
  }
  // Bottom-up: the blocking term is a running maximum of lower-priority C.
  uint64_t longest_lower = 0;
  for (size_t n = count; n > 0; --n) {
    const size_t i = n - 1;
    RtaResult& out = results[i];
    const RtaMessage& m = set[i];
    out.blocking = longest_lower;
    if (m.c > longest_lower) longest_lower = m.c;

    // Instance 0 from eq. 6.12: the first attempt, and q = 0 of the revised
    // analysis (bounded whenever the level's utilisation is below 1).
    uint64_t w0 = 0;
    if (out.first == Bound::kBounded) {
      w0 = queuing_delay(set, i, tau_bit, out.blocking, 0, out.blocking + sum_c(set, i), &out.first);
      out.r_first = m.j + w0 + m.c;
    }
    if (out.revised == Bound::kBounded) {
      if (out.first == Bound::kBounded) {
        revised(set, i, tau_bit, w0, out);
      } else {
        out.revised = out.first;  // horizon reached already at instance 0
      }
    }

    const bool revised_ok = out.revised == Bound::kBounded;
    out.schedulable = revised_ok && out.r <= m.d;
    out.first_optimistic = out.first == Bound::kBounded && (!revised_ok || out.r_first < out.r);
  }
  return RtaStatus::kOk;
}

}  // namespace timing
}  // namespace mb2co
