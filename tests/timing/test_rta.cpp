// Response-time analysis: the examples of seed 000 §2.12-2.13 worked by
// hand, jitter, unbounded levels, and invariants on random sets.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "random_sets.h"
#include "timing/rta.h"

namespace mb2co {
namespace timing {
namespace {

// §2.13 (Davis et al. 2007) in µs, τ_bit = 1 µs (1 Mbit/s): C = 1 ms,
// T = 2.5 / 3.5 / 3.5 ms, D = 2.5 / 3.25 / 3.25 ms.
const RtaMessage kSeed3[] = {
    {1000, 2500, 2500, 0},
    {1000, 3500, 3250, 0},
    {1000, 3500, 3250, 0},
};
constexpr uint64_t kTau = 1;

std::vector<RtaResult> run(const RtaMessage* set, size_t n) {
  std::vector<RtaResult> r(n);
  size_t bad = 0;
  EXPECT_EQ(analyse(set, n, kTau, r.data(), &bad), RtaStatus::kOk);
  return r;
}

TEST(Rta, SeedFirstAttemptGives3ms) {
  const auto r = run(kSeed3, 3);
  ASSERT_EQ(r[2].first, Bound::kBounded);
  EXPECT_EQ(r[2].r_first, 3000u);
}

TEST(Rta, SeedBusyPeriodIs7msWithTwoInstances) {
  Bound b = Bound::kHorizon;
  EXPECT_EQ(blocking_time(kSeed3, 3, 2), 0u);
  EXPECT_EQ(busy_period(kSeed3, 2, 0, &b), 7000u);  // L3(0..4) = 3, 4, 6, 7, 7
  EXPECT_EQ(b, Bound::kBounded);
  const auto r = run(kSeed3, 3);
  EXPECT_EQ(r[2].busy, 7000u);
  EXPECT_EQ(r[2].instances, 2u);
}

TEST(Rta, SeedInstanceDelays) {
  Bound b = Bound::kHorizon;
  // W3,0 from 6.12: 2 → 2; W3,1 from 6.11: 3 → 4 → 5 → 6 → 6.
  EXPECT_EQ(queuing_delay(kSeed3, 2, kTau, 0, 0, 2000, &b), 2000u);
  EXPECT_EQ(queuing_delay(kSeed3, 2, kTau, 0, 1, 3000, &b), 6000u);
  EXPECT_EQ(b, Bound::kBounded);
}

TEST(Rta, SeedRevisedGives3point5msForTheSecondInstance) {
  const auto r = run(kSeed3, 3);
  ASSERT_EQ(r[2].revised, Bound::kBounded);
  EXPECT_EQ(r[2].r, 3500u);  // max(R3,0 = 3, R3,1 = 6 + 1 - 3.5)
  EXPECT_EQ(r[2].critical_instance, 1u);
  EXPECT_TRUE(r[2].first_optimistic);
  EXPECT_FALSE(r[2].schedulable);  // 3.5 ms > D = 3.25 ms
}

TEST(Rta, SeedHigherPrioritiesAsInDavis) {
  const auto r = run(kSeed3, 3);
  // PDO1: blocked by one lower frame (1 ms) then sent: 2 ms.
  EXPECT_EQ(r[0].blocking, 1000u);
  EXPECT_EQ(r[0].r, 2000u);
  EXPECT_EQ(r[0].r_first, 2000u);
  // PDO2: B 1 + PDO1 1 + own 1 = 3 ms; L2 = 5 ms, 2 instances, R2,1 = 1.5 ms.
  EXPECT_EQ(r[1].busy, 5000u);
  EXPECT_EQ(r[1].instances, 2u);
  EXPECT_EQ(r[1].r, 3000u);
  EXPECT_TRUE(r[0].schedulable);
  EXPECT_TRUE(r[1].schedulable);
  EXPECT_FALSE(r[0].first_optimistic);
  EXPECT_FALSE(r[1].first_optimistic);
}

TEST(Rta, JitterWorkedByHand) {
  // H: C 100, T 500, J 450; L: C 100, T 1000. Units of τ_bit = 1.
  const RtaMessage set[] = {{100, 500, 500, 450}, {100, 1000, 1000, 0}};
  const auto r = run(set, 2);
  // L: w = ceil((w + 450 + 1)/500)·100 from 100 → 200 → 200; R = 200 + 100.
  EXPECT_EQ(r[1].r_first, 300u);
  EXPECT_EQ(r[1].r, 300u);
  EXPECT_EQ(r[1].busy, 300u);
  // H: blocked 100, queued up to 450 late: R = 450 + 100 + 100 > T.
  EXPECT_EQ(r[0].blocking, 100u);
  EXPECT_EQ(r[0].r, 650u);
  EXPECT_EQ(r[0].instances, 2u);  // ceil((300 + 450)/500)
  EXPECT_FALSE(r[0].schedulable);
}

TEST(Rta, UtilisationOfOneIsUnboundedButFirstAttemptStillAnswers) {
  const RtaMessage set[] = {{1000, 2000, 2000, 0}, {1000, 2000, 2000, 0}};
  const auto r = run(set, 2);
  EXPECT_EQ(r[0].revised, Bound::kBounded);
  EXPECT_EQ(r[1].revised, Bound::kUtilisation);
  EXPECT_FALSE(r[1].schedulable);
  ASSERT_EQ(r[1].first, Bound::kBounded);  // hp utilisation 0.5
  EXPECT_EQ(r[1].r_first, 2000u);
  EXPECT_TRUE(r[1].first_optimistic);
}

TEST(Rta, ThirdsAddingUpToExactlyOneAreUnbounded) {
  const RtaMessage set[] = {{1, 3, 3, 0}, {1, 3, 3, 0}, {1, 3, 3, 0}};
  const auto r = run(set, 3);
  EXPECT_EQ(r[1].revised, Bound::kBounded);
  EXPECT_EQ(r[2].revised, Bound::kUtilisation);
}

TEST(Rta, BadMessageIsNamed) {
  const RtaMessage set[] = {{1, 3, 3, 0}, {0, 3, 3, 0}};
  std::vector<RtaResult> r(2);
  size_t bad = 99;
  EXPECT_EQ(analyse(set, 2, kTau, r.data(), &bad), RtaStatus::kBadMessage);
  EXPECT_EQ(bad, 1u);
  const RtaMessage huge[] = {{1, kMaxValue + 1, 3, 0}};
  EXPECT_EQ(analyse(huge, 1, kTau, r.data(), &bad), RtaStatus::kBadMessage);
  EXPECT_EQ(bad, 0u);
}

TEST(Rta, RevisedNeverBelowFirstAttemptAndAtLeastBPlusC) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const auto set = random_set(rng, 2 + rng() % 12, 50, 100, 500, 4000, 200);
    const auto r = run(set.data(), set.size());
    for (size_t i = 0; i < set.size(); ++i) {
      if (r[i].revised != Bound::kBounded) continue;
      ASSERT_EQ(r[i].first, Bound::kBounded);
      EXPECT_GE(r[i].r, r[i].r_first);
      EXPECT_EQ(r[i].first_optimistic, r[i].r > r[i].r_first);
      EXPECT_GE(r[i].r, r[i].blocking + set[i].c + set[i].j);
      EXPECT_LE(r[i].r, r[i].busy + set[i].j);
      EXPECT_EQ(r[i].schedulable, r[i].r <= set[i].d);
    }
  }
}

}  // namespace
}  // namespace timing
}  // namespace mb2co
