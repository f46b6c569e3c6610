// The simulator's random numbers are the stream they always were: the
// engine is std::mt19937_64's word for word, and the division-free bound
// gives what `%` gives. A run's reports depend on every draw
// (tests/sim/lab_compare.sh compares whole runs; these tests say which part
// broke).
#include <gtest/gtest.h>

#include <random>

#include "sim/rng.h"

namespace mb2co {
namespace sim {
namespace {

TEST(Rng, EngineIsTheStandardsMt19937x64WordForWord) {
  for (const uint64_t seed :
       {uint64_t{0}, uint64_t{1}, uint64_t{7}, uint64_t{5489}, mix_seed(1, 3), ~uint64_t{0}}) {
    std::mt19937_64 standard(seed);
    Mt19937x64 ours(seed);
    // 10 twists and a part: every word of the state is used several times.
    for (int i = 0; i < 3200; ++i) ASSERT_EQ(ours(), standard()) << "seed " << seed << ", draw " << i;
  }
  // The standard's own check: the 10,000th draw of the default seed.
  Mt19937x64 g(5489);
  for (int i = 1; i < 10000; ++i) g();
  EXPECT_EQ(g(), 9981545732273789042ull);
}

TEST(Rng, DivisorGivesWhatTheDivisionGives) {
  std::mt19937_64 pick(25);
  std::vector<uint64_t> bounds = {1,
                                  2,
                                  3,
                                  5,
                                  7,
                                  10,
                                  1000,
                                  1000000,
                                  1000001,
                                  123456789,
                                  UINT64_MAX,
                                  UINT64_MAX - 1,
                                  (uint64_t{1} << 63) + 1};
  for (unsigned k = 1; k < 64; ++k) {
    bounds.push_back(uint64_t{1} << k);
    bounds.push_back((uint64_t{1} << k) - 1);
    bounds.push_back((uint64_t{1} << k) + 1);
  }
  for (int i = 0; i < 200; ++i) bounds.push_back(pick() >> (pick() % 64));
  for (const uint64_t n : bounds) {
    if (n == 0) continue;
    const Divisor d(n);
    std::vector<uint64_t> values = {0,
                                    1,
                                    n - 1,
                                    n,
                                    n + 1,
                                    UINT64_MAX,
                                    UINT64_MAX - 1,
                                    UINT64_MAX - UINT64_MAX % n,
                                    UINT64_MAX - UINT64_MAX % n - 1};
    for (int i = 0; i < 500; ++i) values.push_back(pick());
    for (const uint64_t v : values) {
      ASSERT_EQ(d.quotient(v), v / n) << v << " / " << n;
      ASSERT_EQ(d.remainder(v), v % n) << v << " % " << n;
    }
  }
}

/// Rng's draws as they were with std::mt19937_64 and `%` (the code before).
class ReferenceRng {
 public:
  explicit ReferenceRng(uint64_t seed) : g_(seed) {}
  uint64_t below(uint64_t n) {
    if (n == 0) return 0;
    const uint64_t limit = UINT64_MAX - UINT64_MAX % n;
    uint64_t v = g_();
    while (v >= limit) v = g_();
    return v % n;
  }

 private:
  std::mt19937_64 g_;
};

TEST(Rng, DrawsWithChangingBoundsAreTheStreamOfBefore) {
  Rng ours(mix_seed(7, 2));
  ReferenceRng before(mix_seed(7, 2));
  std::mt19937_64 pick(3);
  // Bounds as the simulator mixes them: one bound for long stretches (a
  // station's jitter), others in between (a PC's cycle, a fault's chance),
  // 1 (never rejects but UINT64_MAX), and bounds near 2^64 (rejections).
  const uint64_t bounds[] = {1, 2, 20001, 1000000, 200000001, (uint64_t{1} << 63) + 1, UINT64_MAX};
  for (int i = 0; i < 20000; ++i) {
    const uint64_t n = bounds[pick() % 7];
    for (int k = static_cast<int>(pick() % 5); k >= 0; --k) ASSERT_EQ(ours.below(n), before.below(n)) << i;
  }
}

}  // namespace
}  // namespace sim
}  // namespace mb2co
