// FilterPlanner: the plan search in bounded steps gives, byte for byte, the
// plans of the one-shot search it replaced (kept below as the reference,
// verbatim but for names, the sorting and, since issue 25, the splits it
// leaves out (RXB1 with both ids of a back-to-back pair) and their order (longer runs
// first, so that the first of equal plans has the longest run of its start),
// stops and restarts cleanly, and rejects lists it cannot take.
#include <gtest/gtest.h>
#include <string.h>

#include <algorithm>
#include <initializer_list>
#include <random>
#include <set>
#include <vector>

#include "filter_plan.h"

namespace mb2co::mcp2515 {
namespace {

// --- the one-shot planner before FilterPlanner (reference) -----------------

uint8_t ref_distinct_values(const uint16_t* ids, uint8_t n, uint16_t mask) {
  uint8_t count = 0;
  for (uint8_t i = 0; i < n; ++i) {
    bool seen = false;
    for (uint8_t j = 0; j < i && !seen; ++j) seen = ((ids[i] ^ ids[j]) & mask) == 0;
    if (!seen) ++count;
  }
  return count;
}

uint16_t ref_accepted_by(uint8_t values, uint16_t mask) {
  uint16_t accepted = values;
  for (uint16_t bit = 1; bit <= kMaxStandardId; bit = static_cast<uint16_t>(bit << 1)) {
    if ((mask & bit) == 0) accepted = static_cast<uint16_t>(accepted << 1);
  }
  return accepted;
}

uint8_t ref_compact(uint16_t* values, uint8_t n, uint16_t mask) {
  uint8_t kept = 0;
  for (uint8_t i = 0; i < n; ++i) {
    bool seen = false;
    for (uint8_t j = 0; j < kept && !seen; ++j) seen = ((values[i] ^ values[j]) & mask) == 0;
    if (!seen) values[kept++] = values[i];
  }
  return kept;
}

uint16_t ref_group_mask(const uint16_t* ids, uint8_t n, uint8_t filters) {
  uint16_t mask = kMaxStandardId;
  uint16_t values[kMaxSubscribedIds];
  for (uint8_t i = 0; i < n; ++i) values[i] = ids[i];
  uint8_t d = ref_compact(values, n, mask);
  while (d > filters) {
    uint16_t best_mask = 0;
    uint16_t best_cost = 0xFFFF;
    for (uint8_t i = 0; i < d; ++i) {
      for (uint8_t j = 0; j < i; ++j) {
        const uint16_t candidate = static_cast<uint16_t>(mask & ~(values[i] ^ values[j]));
        const uint16_t cost = ref_accepted_by(ref_distinct_values(values, d, candidate), candidate);
        if (cost < best_cost) {
          best_cost = cost;
          best_mask = candidate;
        }
      }
    }
    mask = best_mask;
    d = ref_compact(values, d, mask);
  }
  return mask;
}

void ref_group_filters(const uint16_t* ids, uint8_t n, uint16_t mask, uint16_t* out, uint8_t filters) {
  uint8_t used = 0;
  for (uint8_t i = 0; i < n; ++i) {
    bool seen = false;
    for (uint8_t j = 0; j < used && !seen; ++j) seen = ((out[j] ^ ids[i]) & mask) == 0;
    if (!seen) out[used++] = ids[i];
  }
  for (uint8_t j = used; j < filters; ++j) out[j] = out[0];
}

std::vector<uint16_t> sorted_unique(std::vector<uint16_t> ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

/// True when no two of ids[0..n) are a back-to-back pair: RXB1 may take them.
bool ref_pairs_apart(const uint16_t* ids, uint8_t n) {
  for (uint8_t i = 0; i < n; ++i) {
    for (uint8_t j = 0; j < i; ++j) {
      if (((ids[i] ^ ids[j]) & kBackToBackBits) == 0) return false;
    }
  }
  return true;
}

/// The reference for valid lists (1..kMaxSubscribedIds ids, each <= kMaxStandardId).
void ref_plan_filters(const uint16_t* ids, uint8_t count, FilterPlan& plan) {
  const std::vector<uint16_t> unique = sorted_unique(std::vector<uint16_t>(ids, ids + count));
  const uint16_t* sorted = unique.data();
  const auto n = static_cast<uint8_t>(unique.size());
  uint16_t rest[kMaxSubscribedIds];
  uint16_t best_cost = 0xFFFF;
  for (uint8_t a = 0; a < n; ++a) {
    for (uint8_t b = n; b > a; --b) {
      const uint8_t len = static_cast<uint8_t>(b - a);
      uint8_t r = 0;
      for (uint8_t i = 0; i < n; ++i) {
        if (i < a || i >= b) rest[r++] = sorted[i];
      }
      if (!ref_pairs_apart(rest, r)) continue;
      const uint16_t m0 = ref_group_mask(sorted + a, len, 2);
      const uint16_t cost0 = ref_accepted_by(ref_distinct_values(sorted + a, len, m0), m0);
      const uint16_t bound = static_cast<uint16_t>(cost0 + r);
      if (bound >= best_cost) continue;
      const uint16_t m1 = r ? ref_group_mask(rest, r, 4) : kMaxStandardId;
      const uint16_t cost =
          static_cast<uint16_t>(cost0 + (r ? ref_accepted_by(ref_distinct_values(rest, r, m1), m1) : 0u));
      if (cost >= best_cost) continue;
      best_cost = cost;
      plan.mask[0] = m0;
      plan.mask[1] = m1;
      ref_group_filters(sorted + a, len, m0, plan.filter, 2);
      if (r) {
        ref_group_filters(rest, r, m1, plan.filter + 2, 4);
      } else {
        for (uint8_t f = 2; f < 6; ++f) plan.filter[f] = plan.filter[0];
      }
    }
  }
  uint16_t accepted = 0;
  for (uint16_t id = 0; id <= kMaxStandardId; ++id) {
    if (plan_accepts(plan, id)) ++accepted;
  }
  plan.accepted_ids = accepted;
  plan.exact = accepted == n;
}

// --- helpers ---------------------------------------------------------------

void expect_same(const FilterPlan& got, const FilterPlan& want, const std::vector<uint16_t>& ids) {
  std::string list;
  for (uint16_t id : ids) list += std::to_string(id) + " ";
  EXPECT_EQ(got.mask[0], want.mask[0]) << list;
  EXPECT_EQ(got.mask[1], want.mask[1]) << list;
  for (int f = 0; f < 6; ++f) EXPECT_EQ(got.filter[f], want.filter[f]) << "RXF" << f << " of " << list;
  EXPECT_EQ(got.exact, want.exact) << list;
  EXPECT_EQ(got.accepted_ids, want.accepted_ids) << list;
}

/// Steps `planner` to the end; the number of steps it took.
int run(FilterPlanner& planner) {
  int steps = 1;
  while (!planner.step()) ++steps;
  return steps;
}

/// Id lists of three kinds: uniform over the 2048 ids, CANopen-like (function
/// code and node id, as a node consumes them), and clustered (few bits apart:
/// many merges tie).
std::vector<uint16_t> random_ids(std::mt19937& rng, int kind) {
  std::uniform_int_distribution<int> len_dist(1, kMaxSubscribedIds);
  std::vector<uint16_t> ids(static_cast<size_t>(len_dist(rng)));
  for (auto& id : ids) {
    if (kind == 0) {
      id = static_cast<uint16_t>(std::uniform_int_distribution<int>(0, kMaxStandardId)(rng));
    } else if (kind == 1) {
      static const uint16_t kBases[] = {0x000, 0x080, 0x180, 0x200, 0x280, 0x300,
                                        0x380, 0x400, 0x480, 0x500, 0x600, 0x700};
      const uint16_t base = kBases[std::uniform_int_distribution<int>(0, 11)(rng)];
      id = static_cast<uint16_t>(base + (base == 0 ? 0 : std::uniform_int_distribution<int>(1, 8)(rng)));
    } else {
      id = static_cast<uint16_t>(0x180 + std::uniform_int_distribution<int>(0, 31)(rng));
    }
  }
  return ids;
}

// --- tests -------------------------------------------------------------------

TEST(FilterPlanner, SameBytesAsTheOneShotSearchForRandomLists) {
  std::mt19937 rng(20240611);
  int multi_step_plans = 0;
  for (int round = 0; round < 1500; ++round) {
    const std::vector<uint16_t> ids = random_ids(rng, round % 3);
    FilterPlan want;
    memset(&want, 0, sizeof want);
    ref_plan_filters(ids.data(), static_cast<uint8_t>(ids.size()), want);

    FilterPlan once;
    memset(&once, 0xA5, sizeof once);
    ASSERT_TRUE(plan_filters(ids.data(), static_cast<uint8_t>(ids.size()), once));
    expect_same(once, want, ids);

    const std::vector<uint16_t> sorted = sorted_unique(ids);
    FilterPlanner planner{};
    planner.start(sorted.data(), static_cast<uint8_t>(sorted.size()));
    if (run(planner) > 1) ++multi_step_plans;
    ASSERT_TRUE(planner.done());
    FilterPlan stepped;
    memset(&stepped, 0x5A, sizeof stepped);
    planner.plan(stepped);
    expect_same(stepped, want, ids);
    if (HasFailure()) return;
  }
  EXPECT_GT(multi_step_plans, 300) << "long lists take several steps";
}

TEST(FilterPlanner, GatewayListsTakeManyBoundedSteps) {
  // Node 2 of a 4-station ring (passtime_main.cpp), 9 and 12 ids.
  const uint16_t ids[] = {0x000, 0x080, 0x181, 0x183, 0x281, 0x602, 0x701, 0x702, 0x703, 0x704, 0x705, 0x706};
  for (uint8_t n : {uint8_t{9}, uint8_t{12}}) {
    FilterPlan want;
    ref_plan_filters(ids, n, want);
    FilterPlanner planner{};
    planner.start(ids, n);
    EXPECT_TRUE(planner.busy());
    EXPECT_GT(run(planner), 10) << int{n} << " ids: many steps, each a small piece";
    FilterPlan got;
    planner.plan(got);
    expect_same(got, want, std::vector<uint16_t>(ids, ids + n));
  }
}

TEST(FilterPlanner, AllIdsInRxb0LeaveRxb1RepeatingRxf0Exactly) {
  // Two ids: RXB0 alone passes both exactly (a tie with one id in each
  // buffer, and the longer run wins), so RXB1 has no ids of its own: its
  // exact mask and RXF0 repeated in every filter add nothing.
  const uint16_t ids[] = {0x181, 0x182};
  FilterPlanner planner{};
  planner.start(ids, 2);
  run(planner);
  ASSERT_TRUE(planner.done());
  FilterPlan got;
  memset(&got, 0x5A, sizeof got);
  planner.plan(got);
  EXPECT_EQ(got.mask[0], kMaxStandardId);
  EXPECT_EQ(got.mask[1], kMaxStandardId);
  EXPECT_EQ(got.filter[0], 0x181);
  EXPECT_EQ(got.filter[1], 0x182);
  for (int f = 2; f < 6; ++f) EXPECT_EQ(got.filter[f], 0x181) << "RXF" << f;
  EXPECT_TRUE(got.exact);
  EXPECT_EQ(got.accepted_ids, 2);
  FilterPlan want;
  ref_plan_filters(ids, 2, want);
  expect_same(got, want, std::vector<uint16_t>(ids, ids + 2));
}

TEST(FilterPlanner, StartOverMidwayGivesTheNewListsPlan) {
  const uint16_t first[] = {0x000, 0x080, 0x181, 0x183, 0x281, 0x602, 0x701, 0x703, 0x704, 0x705};
  const uint16_t second[] = {0x000, 0x080, 0x182, 0x184, 0x282, 0x603, 0x702, 0x704};
  FilterPlanner planner{};
  planner.start(first, 10);
  for (int i = 0; i < 5; ++i) ASSERT_FALSE(planner.step());
  planner.start(second, 8);
  run(planner);
  ASSERT_TRUE(planner.done());
  FilterPlan got, want;
  planner.plan(got);
  ref_plan_filters(second, 8, want);
  expect_same(got, want, std::vector<uint16_t>(second, second + 8));
}

TEST(FilterPlanner, IdleUntilStartedAndAfterStop) {
  FilterPlanner planner{};  // all zero: idle
  EXPECT_FALSE(planner.busy());
  EXPECT_FALSE(planner.done());
  EXPECT_TRUE(planner.step()) << "no work";
  const uint16_t ids[] = {0x000, 0x080, 0x181, 0x183, 0x281, 0x602, 0x701, 0x703, 0x704};
  planner.start(ids, 9);
  ASSERT_FALSE(planner.step());
  planner.stop();
  EXPECT_FALSE(planner.busy());
  EXPECT_FALSE(planner.done());
  EXPECT_TRUE(planner.step());
}

// --- acceptance ranges into the planner's id list --------------------------

std::vector<uint16_t> admitted(std::initializer_list<CanIdRange> ranges) {
  uint16_t ids[kMaxSubscribedIds];
  const uint8_t n = admitted_ids(ranges.begin(), static_cast<uint8_t>(ranges.size()), ids);
  return std::vector<uint16_t>(ids, ids + n);
}

TEST(AdmittedIds, OneIdRangesAreSortedWithoutDuplicates) {
  EXPECT_EQ(admitted({{0x701, 0x7FF}, {0x000, 0x7FF}, {0x601, 0x7FF}, {0x080, 0x7FF}, {0x701, 0x7FF}}),
            (std::vector<uint16_t>{0x000, 0x080, 0x601, 0x701}));
}

TEST(AdmittedIds, TheRemoteBitIsNoIdBit) {
  // Data only, remote only: the chip filters both alike (a superset).
  EXPECT_EQ(admitted({{0x181, 0xFFF}, {0x281 | kCanRangeRemote, 0xFFF}, {0x0FF, 0x7FF}}),
            (std::vector<uint16_t>{0x0FF, 0x181, 0x281}));
}

TEST(AdmittedIds, MoreThanThePlannerTakesIsNone) {
  std::vector<CanIdRange> twelve, thirteen;
  for (uint16_t i = 0; i < kMaxSubscribedIds; ++i)
    twelve.push_back(CanIdRange{static_cast<uint16_t>(0x100 + i), 0x7FF});
  thirteen = twelve;
  thirteen.push_back(CanIdRange{0x200, 0x7FF});
  uint16_t ids[kMaxSubscribedIds];
  EXPECT_EQ(admitted_ids(twelve.data(), kMaxSubscribedIds, ids), kMaxSubscribedIds);
  EXPECT_EQ(admitted_ids(thirteen.data(), kMaxSubscribedIds + 1, ids), 0) << "filters stay open";
  thirteen.back() = twelve.front();  // a repeat is no extra id
  EXPECT_EQ(admitted_ids(thirteen.data(), kMaxSubscribedIds + 1, ids), kMaxSubscribedIds);
  EXPECT_EQ(admitted_ids(twelve.data(), 0, ids), 0) << "none: nothing to plan";
}

TEST(AdmittedIds, RangesOfSeveralIdsKeepTheFiltersOpen) {
  // A network gateway's 580h-5FFh, every remote frame, even two ids: the
  // chip keeps them as a superset (open).
  EXPECT_TRUE(admitted({{0x000, 0x7FF}, {0x580, 0x780}}).empty());
  EXPECT_TRUE(admitted({{0x000, 0x7FF}, {kCanRangeRemote, kCanRangeRemote}}).empty());
  EXPECT_TRUE(admitted({{0x180, 0x7FE}}).empty());
}

}  // namespace
}  // namespace mb2co::mcp2515
