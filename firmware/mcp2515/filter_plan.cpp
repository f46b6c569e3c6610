#include "filter_plan.h"

namespace mb2co {
namespace mcp2515 {
namespace {

constexpr uint8_t kFiltersRxB0 = 2;
constexpr uint8_t kFiltersRxB1 = 4;

/// How many different values ids[i] & mask takes over i in [0, n). O(n^2).
uint8_t distinct_values(const uint16_t* ids, uint8_t n, uint16_t mask) {
  uint8_t count = 0;
  for (uint8_t i = 0; i < n; ++i) {
    bool seen = false;
    for (uint8_t j = 0; j < i && !seen; ++j) seen = ((ids[i] ^ ids[j]) & mask) == 0;
    if (!seen) ++count;
  }
  return count;
}

/// Ids that a group with `mask` and `values` filters accepts: values * 2^(cleared bits).
uint16_t accepted_by(uint8_t values, uint16_t mask) {
  uint16_t accepted = values;
  for (uint16_t bit = 1; bit <= kMaxStandardId; bit = static_cast<uint16_t>(bit << 1)) {
    if ((mask & bit) == 0) accepted = static_cast<uint16_t>(accepted << 1);
  }
  return accepted;
}

/// Keeps the first of each group of values equal under `mask`; returns how
/// many remain in values[0..).
uint8_t compact(uint16_t* values, uint8_t n, uint16_t mask) {
  uint8_t kept = 0;
  for (uint8_t i = 0; i < n; ++i) {
    bool seen = false;
    for (uint8_t j = 0; j < kept && !seen; ++j) seen = ((values[i] ^ values[j]) & mask) == 0;
    if (!seen) values[kept++] = values[i];
  }
  return kept;
}

/// Widest-fitting mask for one buffer: starts exact and, while more distinct
/// values remain than the buffer has filters, merges the pair of values whose
/// merge (clearing the bits they differ in) lets the fewest ids through. Works
/// on one representative per distinct value: ids equal under a mask stay
/// equal under any narrower one, so the counts are the same.
uint16_t group_mask(const uint16_t* ids, uint8_t n, uint8_t filters) {
  uint16_t mask = kMaxStandardId;
  uint16_t values[kMaxSubscribedIds];
  for (uint8_t i = 0; i < n; ++i) values[i] = ids[i];
  uint8_t d = compact(values, n, mask);
  while (d > filters) {
    uint16_t best_mask = 0;
    uint16_t best_cost = 0xFFFF;
    for (uint8_t i = 0; i < d; ++i) {
      for (uint8_t j = 0; j < i; ++j) {
        const uint16_t candidate = static_cast<uint16_t>(mask & ~(values[i] ^ values[j]));
        const uint16_t cost = accepted_by(distinct_values(values, d, candidate), candidate);
        if (cost < best_cost) {
          best_cost = cost;
          best_mask = candidate;
        }
      }
    }
    mask = best_mask;
    d = compact(values, d, mask);  // at least the merged pair became one: the loop ends
  }
  return mask;
}

/// Fills `out[0..filters)` with the distinct masked values (first one repeated
/// into unused slots, so unused filters accept nothing new).
void group_filters(const uint16_t* ids, uint8_t n, uint16_t mask, uint16_t* out, uint8_t filters) {
  uint8_t used = 0;
  for (uint8_t i = 0; i < n; ++i) {
    bool seen = false;
    for (uint8_t j = 0; j < used && !seen; ++j) seen = ((out[j] ^ ids[i]) & mask) == 0;
    if (!seen) out[used++] = ids[i];  // group_mask guarantees used <= filters
  }
  for (uint8_t j = used; j < filters; ++j) out[j] = out[0];
}

}  // namespace

bool plan_accepts(const FilterPlan& plan, uint16_t id) {
  for (uint8_t f = 0; f < 6; ++f) {
    const uint16_t mask = plan.mask[f < kFiltersRxB0 ? 0 : 1];
    if (((id ^ plan.filter[f]) & mask) == 0) return true;
  }
  return false;
}

bool plan_filters(const uint16_t* ids, uint8_t count, FilterPlan& plan) {
  if (count == 0 || count > kMaxSubscribedIds) return false;
  // Sorted, de-duplicated copy: CANopen puts the function code in the high
  // bits, so neighbours in id order share masks well.
  uint16_t sorted[kMaxSubscribedIds];
  uint8_t n = 0;
  for (uint8_t i = 0; i < count; ++i) {
    const uint16_t id = ids[i];
    if (id > kMaxStandardId) return false;
    uint8_t at = n;
    while (at > 0 && sorted[at - 1] > id) --at;
    if (at > 0 && sorted[at - 1] == id) continue;
    for (uint8_t k = n; k > at; --k) sorted[k] = sorted[k - 1];
    sorted[at] = id;
    ++n;
  }

  // RXB0 takes a run sorted[a, b), RXB1 the ids before and after it. Keep the
  // split letting the fewest ids through; on a tie the longer run, since
  // RXB0's ids roll over into RXB1 (two buffers of depth, RXB1's own one).
  uint16_t rest[kMaxSubscribedIds];
  uint16_t best_cost = 0xFFFF;
  uint8_t best_len = 0;
  for (uint8_t a = 0; a < n; ++a) {
    for (uint8_t b = static_cast<uint8_t>(a + 1); b <= n; ++b) {
      const uint8_t len = static_cast<uint8_t>(b - a);
      uint8_t r = 0;
      for (uint8_t i = 0; i < n; ++i) {
        if (i < a || i >= b) rest[r++] = sorted[i];
      }
      const uint16_t m0 = group_mask(sorted + a, len, kFiltersRxB0);
      const uint16_t cost0 = accepted_by(distinct_values(sorted + a, len, m0), m0);
      // RXB1 lets at least its r ids through: skip its (costly) search when
      // even that cannot beat the best split so far.
      const uint16_t bound = static_cast<uint16_t>(cost0 + r);
      if (bound > best_cost || (bound == best_cost && len <= best_len)) continue;
      const uint16_t m1 = r ? group_mask(rest, r, kFiltersRxB1) : kMaxStandardId;
      const uint16_t cost = static_cast<uint16_t>(cost0 + (r ? accepted_by(distinct_values(rest, r, m1), m1) : 0u));
      if (cost > best_cost || (cost == best_cost && len <= best_len)) continue;
      best_cost = cost;
      best_len = len;
      plan.mask[0] = m0;
      plan.mask[1] = m1;
      group_filters(sorted + a, len, m0, plan.filter, kFiltersRxB0);
      if (r) {
        group_filters(rest, r, m1, plan.filter + kFiltersRxB0, kFiltersRxB1);
      } else {
        for (uint8_t f = kFiltersRxB0; f < 6; ++f) plan.filter[f] = plan.filter[0];
      }
    }
  }

  uint16_t accepted = 0;
  for (uint16_t id = 0; id <= kMaxStandardId; ++id) {
    if (plan_accepts(plan, id)) ++accepted;
  }
  plan.accepted_ids = accepted;
  plan.exact = accepted == n;
  return true;
}

}  // namespace mcp2515
}  // namespace mb2co
