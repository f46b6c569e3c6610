// The replayed worst-case busy period: the seed's figure of §2.13, and the
// analysis checked against the step-by-step schedule on random sets.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "random_sets.h"
#include "timing/bus_trace.h"

namespace mb2co {
namespace timing {
namespace {

struct Trace {
  std::vector<BusSegment> segments;
  bool truncated = false;
};

Trace trace(const std::vector<RtaMessage>& set, size_t i, uint64_t tau, size_t capacity = 100000) {
  Trace t;
  t.segments.resize(capacity);
  std::vector<uint64_t> sent(i + 1);
  t.segments.resize(trace_busy_period(set.data(), set.size(), i, tau, sent.data(), t.segments.data(),
                                      capacity, &t.truncated));
  return t;
}

// Response of each traced instance of i: end + J - q T (eq. 6.13).
uint64_t worst_traced_response(const Trace& t, const RtaMessage& m, size_t i) {
  uint64_t worst = 0;
  for (const BusSegment& s : t.segments) {
    if (s.message != i) continue;
    const uint64_t r = s.end + m.j - s.instance * m.t;
    if (r > worst) worst = r;
  }
  return worst;
}

TEST(BusTrace, SeedFigureOfSection2_13) {
  const std::vector<RtaMessage> set = {{1000, 2500, 2500, 0}, {1000, 3500, 3250, 0}, {1000, 3500, 3250, 0}};
  const Trace t = trace(set, 2, 1);
  ASSERT_FALSE(t.truncated);
  // PDO1 PDO2 PDO3 | PDO1 (2.5) PDO2 (3.5) PDO1 (5.0) PDO3 (3.5) -> ends at 7.
  const size_t who[] = {0, 1, 2, 0, 1, 0, 2};
  ASSERT_EQ(t.segments.size(), 7u);
  for (size_t s = 0; s < 7; ++s) {
    EXPECT_EQ(t.segments[s].message, who[s]) << s;
    EXPECT_EQ(t.segments[s].start, 1000u * s) << s;
  }
  EXPECT_EQ(t.segments[6].instance, 1u);
  EXPECT_EQ(worst_traced_response(t, set[2], 2), 3500u);
}

TEST(BusTrace, BlockerComesFirst) {
  const std::vector<RtaMessage> set = {{100, 1000, 1000, 0}, {300, 5000, 5000, 0}, {200, 5000, 5000, 0}};
  const Trace t = trace(set, 0, 1);
  ASSERT_EQ(t.segments.size(), 2u);
  EXPECT_EQ(t.segments[0].message, 1u);  // the longest lower-priority frame
  EXPECT_EQ(t.segments[1].start, 300u);
}

TEST(BusTrace, TruncatesAtCapacity) {
  const std::vector<RtaMessage> set = {{1000, 2500, 2500, 0}, {1000, 3500, 3250, 0}, {1000, 3500, 3250, 0}};
  const Trace t = trace(set, 2, 1, 3);
  EXPECT_TRUE(t.truncated);
  EXPECT_EQ(t.segments.size(), 3u);
}

TEST(BusTrace, AnalysisMatchesTheReplayedSchedule) {
  std::mt19937 rng(11);
  int optimistic_cases = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const size_t n = 2 + rng() % 8;
    const std::vector<RtaMessage> set = random_set(rng, n, 40, 120, 300, 1200, 150);
    std::vector<RtaResult> r(n);
    size_t bad = 0;
    ASSERT_EQ(analyse(set.data(), n, 1, r.data(), &bad), RtaStatus::kOk);
    for (size_t i = 0; i < n; ++i) {
      if (r[i].revised != Bound::kBounded) continue;
      const Trace t = trace(set, i, 1);
      ASSERT_FALSE(t.truncated);
      EXPECT_EQ(t.segments.back().end, r[i].busy) << trial << ' ' << i;
      EXPECT_EQ(worst_traced_response(t, set[i], i), r[i].r) << trial << ' ' << i;
      if (r[i].first_optimistic) ++optimistic_cases;
    }
  }
  EXPECT_GT(optimistic_cases, 0);  // the random sets do exercise §2.13
}

}  // namespace
}  // namespace timing
}  // namespace mb2co
