#include "filter_plan.h"

namespace mb2co {
namespace mcp2515 {
namespace {

constexpr uint8_t kFiltersRxB0 = 2;
constexpr uint8_t kFiltersRxB1 = 4;
constexpr uint16_t kNoCost = 0xFFFF;
constexpr uint16_t kNoId = 0xFFFF;       ///< above every standard id
constexpr uint8_t kStandardIdBits = 11;  ///< kMaxStandardId = 2^11 - 1
/// Work charged for a candidate merge besides its comparisons (its mask's
/// width, bookkeeping), and for the end of a group search.
constexpr uint16_t kPairWork = 8;

/// Ids `values` distinct filter values with `mask` accept: values * 2^(bits
/// the mask clears).
__attribute__((noinline)) uint16_t accepted_by(uint16_t values, uint16_t mask) {
  for (uint8_t bit = 0; bit < kStandardIdBits; ++bit, mask = static_cast<uint16_t>(mask >> 1)) {
    if ((mask & 1) == 0) values = static_cast<uint16_t>(values << 1);
  }
  return values;
}

/// Adds `id` to the sorted, duplicate-free ids[0..n); false when it is new
/// and kMaxSubscribedIds are there already.
bool insert_id(uint16_t* ids, uint8_t& n, uint16_t id) {
  uint8_t at = n;
  while (at > 0 && ids[at - 1] > id) --at;
  if (at > 0 && ids[at - 1] == id) return true;
  if (n == kMaxSubscribedIds) return false;
  for (uint8_t k = n; k > at; --k) ids[k] = ids[k - 1];
  ids[at] = id;
  ++n;
  return true;
}

}  // namespace

// Ascending by selection: each round takes the least id not yet taken (at
// most kMaxSubscribedIds + 1 rounds over the ranges: no sort, no shifting).
uint8_t admitted_ids(const CanIdRange* ranges, uint8_t count, uint16_t* ids) {
  uint8_t n = 0;
  uint16_t floor = 0;  // every id below it is taken
  for (;;) {
    uint16_t next = kNoId;
    for (const CanIdRange* r = ranges; r < ranges + count; ++r) {
      if ((r->mask & kMaxStandardId) != kMaxStandardId) return 0;  // more than one id: open
      const uint16_t id = r->id & kMaxStandardId;
      if (id >= floor && id < next) next = id;
    }
    if (next == kNoId) return n;
    if (n == kMaxSubscribedIds) return 0;
    ids[n++] = next;
    floor = static_cast<uint16_t>(next + 1);
  }
}

bool plan_accepts(const FilterPlan& plan, uint16_t id) {
  for (uint8_t f = 0; f < 6; ++f) {
    const uint16_t mask = plan.mask[f < kFiltersRxB0 ? 0 : 1];
    if (((id ^ plan.filter[f]) & mask) == 0) return true;
  }
  return false;
}

// The search: RXB0 takes a run ids_[a, b) of the sorted ids, RXB1 the ids
// before and after it. Every run is tried, longer runs of a start first:
// (0,n), (0,n-1) .. (0,1), (1,n) .. (n-1,n); a split whose RXB1 would take
// both ids of a back-to-back pair (kBackToBackBits) is out (the run of all ids leaves
// RXB1 none, so a plan is always found). The split letting the fewest ids
// through wins, on a tie the first: of its start, the longest run, since
// RXB0's ids roll over into RXB1 (two buffers of depth, RXB1's own one).
// For each buffer a greedy mask search: start exact and,
// while more distinct values remain than the buffer has filters, merge the
// pair of values whose merge (clearing the bits they differ in) lets the
// fewest ids through (the first such pair, in the order (1,0), (2,0), (2,1),
// (3,0) ..). It works on one id per distinct value: ids equal under a mask
// stay equal under any narrower one, so the counts are the same.

void FilterPlanner::start(const uint16_t* ids, uint8_t count) {
  ids_ = ids;
  n_ = count;
  a_ = 0;
  b_ = static_cast<uint8_t>(count + 1);
  best_cost_ = kNoCost;
  next_split();
}

/// Keeps in `out`, in order, the first id of each distinct value under `mask`
/// among the ids of ids_[0..n_) inside the run [a, b) (`run`) or outside it
/// (!run), then repeats out[0] into out[used..filters) (unused filters then
/// accept nothing new; with no ids at all out[0] stays as it was); returns
/// how many are distinct.
__attribute__((noinline)) uint8_t FilterPlanner::distinct(uint8_t a, uint8_t b, bool run, uint16_t mask,
                                                          uint16_t* out, uint8_t filters) const {
  uint8_t used = 0;
  for (uint8_t i = 0; i < n_; ++i) {
    if ((i >= a && i < b) != run) continue;
    uint8_t j = 0;
    while (j < used && ((out[j] ^ ids_[i]) & mask) != 0) ++j;
    if (j == used) out[used++] = ids_[i];  // the search guarantees used <= filters
  }
  for (uint8_t j = used; j < filters; ++j) out[j] = out[0];
  return used;
}

__attribute__((noinline)) void FilterPlanner::begin_round(uint16_t mask) {
  mask_ = mask;
  i_ = 1;
  j_ = 0;
  round_cost_ = kNoCost;
}

bool FilterPlanner::loses(uint16_t cost) const {
  return cost >= best_cost_;
}

void FilterPlanner::consider(uint16_t cost, uint16_t mask1) {
  if (loses(cost)) return;
  best_cost_ = cost;
  best_a_ = a_;
  best_b_ = b_;
  best_m0_ = m0_;
  best_m1_ = mask1;
}

void FilterPlanner::next_split() {
  if (--b_ == a_) {
    ++a_;
    b_ = n_;
  }
  phase_ = a_ < n_ ? kRun : kDone;
  begin_round(kMaxStandardId);
}

void FilterPlanner::finish_group(uint8_t values, uint16_t* scratch) {
  const uint16_t cost = accepted_by(values, mask_);
  if (phase_ == kRest) {
    consider(static_cast<uint16_t>(cost0_ + cost), mask_);
  } else {
    m0_ = mask_;
    cost0_ = cost;
    const uint8_t rest = static_cast<uint8_t>(n_ - (b_ - a_));
    // The split is out when RXB1's ids are fewer distinct under
    // kBackToBackBits than ids (both of a back-to-back pair).
    if (!loses(static_cast<uint16_t>(cost + rest)) &&
        distinct(a_, b_, false, kBackToBackBits, scratch, 0) == rest) {
      // RXB1 lets at least its own ids through: its (costly) search only
      // when even that could beat the best split so far. Without ids it
      // ends at once, exact and letting none through.
      phase_ = kRest;
      begin_round(kMaxStandardId);
      return;
    }
  }
  next_split();
}

__attribute__((noinline)) bool FilterPlanner::step() {
  static_assert(kRun * kFiltersRxB0 == kFiltersRxB0 && kRest * kFiltersRxB0 == kFiltersRxB1,
                "a group's filters: its phase times RXB0's");
  uint16_t values[kMaxSubscribedIds];
  uint8_t d = 0;
  // Every pass of the loop starts by (re)loading the group's distinct
  // values when `d` is 0: at the start, after a group or a round ended.
  uint16_t work = 0;
  while (busy() && work < kStepWork) {
    if (d == 0) {
      // Charged twice: a group's end (finish_group) looks for back-to-back
      // pairs in RXB1 with another distinct().
      d = distinct(a_, b_, phase_ == kRun, mask_, values, 0);
      work = static_cast<uint16_t>(work + 2u * n_ + kPairWork);
    }
    if (d <= static_cast<uint8_t>(phase_ * kFiltersRxB0)) {
      finish_group(d, values);  // values are loaded again: d = 0
      d = 0;
      continue;
    }
    // One candidate: merge values i_ and j_. Counting the distinct values
    // under it stops once the count shows it cannot beat the round's best.
    const uint16_t candidate = static_cast<uint16_t>(mask_ & ~(values[i_] ^ values[j_]));
    const uint16_t per_value = accepted_by(1, candidate);
    uint16_t cost = 0;
    for (uint8_t k = 0; k < d && cost < round_cost_; ++k) {
      uint8_t e = 0;
      while (e < k && ((values[k] ^ values[e]) & candidate) != 0) ++e;
      work = static_cast<uint16_t>(work + k);
      if (e == k) cost = static_cast<uint16_t>(cost + per_value);
    }
    work = static_cast<uint16_t>(work + kPairWork);
    if (cost < round_cost_) {
      round_cost_ = cost;
      round_mask_ = candidate;
    }
    if (++j_ < i_) continue;
    j_ = 0;
    if (++i_ < d) continue;
    // Round over: take its best merge (at least the merged pair became one
    // value, so the search ends).
    begin_round(round_mask_);
    d = 0;
  }
  return !busy();
}

void FilterPlanner::plan(FilterPlan& out) const {
  const uint16_t m0 = best_m0_;
  const uint16_t m1 = best_m1_;
  out.mask[0] = m0;
  out.mask[1] = m1;
  // Standard ids passing, counted without trying all 2048: the values of one
  // buffer accept disjoint sets, so |RXB0 u RXB1| = |RXB0| + |RXB1| (the
  // search's cost) minus the ids both pass; a value of each has those in
  // common when they agree on the bits both masks keep: 2^(bits neither
  // keeps) ids.
  uint16_t accepted = best_cost_;
  const uint8_t d0 = distinct(best_a_, best_b_, true, m0, out.filter, kFiltersRxB0);
  uint16_t* const rxb1 = out.filter + kFiltersRxB0;
  rxb1[0] = out.filter[0];  // an RXB1 without ids repeats RXF0 (exact m1): d1 0
  const uint8_t d1 = distinct(best_a_, best_b_, false, m1, rxb1, kFiltersRxB1);
  const uint16_t common = accepted_by(1, m0 | m1);
  for (const uint16_t* p = out.filter; p < out.filter + d0; ++p) {
    for (const uint16_t* q = rxb1; q < rxb1 + d1; ++q) {
      if (((*p ^ *q) & m0 & m1) == 0) accepted = static_cast<uint16_t>(accepted - common);
    }
  }
  out.accepted_ids = accepted;
  out.exact = accepted == n_;
}

bool plan_filters(const uint16_t* ids, uint8_t count, FilterPlan& plan) {
  if (count == 0 || count > kMaxSubscribedIds) return false;
  // Sorted, de-duplicated copy: CANopen puts the function code in the high
  // bits, so neighbours in id order share masks well.
  uint16_t sorted[kMaxSubscribedIds];
  uint8_t n = 0;
  for (uint8_t i = 0; i < count; ++i) {
    if (ids[i] > kMaxStandardId) return false;
    insert_id(sorted, n, ids[i]);  // count <= kMaxSubscribedIds: room for every id
  }
  FilterPlanner planner;
  planner.start(sorted, n);
  while (!planner.step()) {
  }
  planner.plan(plan);
  return true;
}

}  // namespace mcp2515
}  // namespace mb2co
