// The week-13 SYNC labs (seed 000 §5.2, §5.3) and §11's simpler alternative
// on the simulated line: every measurement inside its shared/timing bound at
// each bit rate, and a deliberately wrong bound turns the verdict to FAIL.
#include <gtest/gtest.h>

#include "sim/lab_bound.h"
#include "sim/sync_scenarios.h"

namespace mb2co {
namespace sim {
namespace {

LineConfig line4(uint64_t seed = 5) {
  LineConfig c;  // 4 stations in a chain
  c.seed = seed;
  return c;
}

SyncLabConfig at(uint32_t kbit, uint8_t type = 1) {
  SyncLabConfig l;
  l.bitrate_kbit = kbit;
  l.transmission_type = type;
  return l;
}

const timing::MessageSpec* find(const std::vector<timing::MessageSpec>& set, uint32_t id) {
  for (const timing::MessageSpec& m : set) {
    if (m.id == id) return &m;
  }
  return nullptr;
}

TEST(SyncLab, RoundTripsLieWithinTheBoundAtEveryBitRate) {
  for (uint32_t kbit : {125u, 250u, 500u, 1000u}) {
    SCOPED_TRACE(kbit);
    const SyncResult r = sync_roundtrip_scenario(line4(), at(kbit), 200, nullptr, nullptr);
    ASSERT_TRUE(r.bound_ok) << r.error;
    EXPECT_EQ(r.samples_ns.size(), 200u);
    EXPECT_GE(r.stats.min_ns, r.bound.best_ns);
    EXPECT_LE(r.stats.max_ns, r.bound.worst_ns);
    EXPECT_EQ(r.outside, 0u);
    EXPECT_TRUE(r.ok);
    // Never faster than the two bare frames and the shortest pass handling a frame.
    EXPECT_GE(r.stats.min_ns, timing::sync_frame_best_ns(r.params) + timing::pdo_frame_best_ns(r.params) +
                                  uint64_t{r.params.pass_min_us} * 1000u);
  }
}

TEST(SyncLab, RoundTripShrinksWithTheBitRate) {
  const SyncResult slow = sync_roundtrip_scenario(line4(), at(125), 100, nullptr, nullptr);
  const SyncResult fast = sync_roundtrip_scenario(line4(), at(1000), 100, nullptr, nullptr);
  // Both frames take 8 times longer at 125 kbit/s: 2 x 44 bits of 7 µs more at least.
  EXPECT_GT(slow.stats.min_ns, fast.stats.min_ns + 600000u);
  EXPECT_GT(slow.bound.worst_ns, fast.bound.worst_ns);
}

TEST(SyncLab, APeriodNotAboveTheWorstRoundTripIsNotMeasured) {
  // A SYNC every 2 ms while an answer may take 3.4 ms at 1 Mbit/s: paired
  // with the last SYNC, a late answer would look shorter than its frames.
  SyncLabConfig lab = at(1000);
  lab.sync_period_us = 2000;
  const SyncResult r = sync_roundtrip_scenario(line4(), lab, 100, nullptr, nullptr);
  ASSERT_TRUE(r.bound_ok);
  EXPECT_GE(r.bound.worst_ns, 2000000u);
  EXPECT_TRUE(r.samples_ns.empty());
  EXPECT_NE(r.error.find("not measured"), std::string::npos) << r.error;
  EXPECT_FALSE(r.ok);
}

TEST(SyncLab, ResponseUnderSyncLiesWithinItsMinAndMaxAtEveryBitRate) {
  for (uint32_t kbit : {125u, 250u, 500u, 1000u}) {
    SCOPED_TRACE(kbit);
    const SyncResult r = sync_latency_scenario(line4(), at(kbit), 150, nullptr, nullptr);
    ASSERT_TRUE(r.bound_ok) << r.error;
    EXPECT_EQ(r.samples_ns.size(), 150u);
    EXPECT_EQ(r.lost, 0u);
    EXPECT_EQ(r.outside, 0u);
    EXPECT_TRUE(r.ok);
    EXPECT_GT(r.syncs, 100u);
  }
}

TEST(SyncLab, EveryThirdSyncWaitsLongerAndStaysInsideItsBound) {
  const SyncResult one = sync_latency_scenario(line4(), at(500, 1), 150, nullptr, nullptr);
  const SyncResult three = sync_latency_scenario(line4(), at(500, 3), 150, nullptr, nullptr);
  EXPECT_TRUE(three.ok) << three.error;
  EXPECT_EQ(three.outside, 0u);
  // Up to 3 periods of 10 ms instead of 1 before the PDO is sampled.
  EXPECT_GT(three.stats.max_ns, one.stats.max_ns + 5000000u);
  EXPECT_EQ(three.bound.worst_ns - one.bound.worst_ns, 2u * 10000000u);
}

TEST(SyncLab, ABoundAssumingATooShortSyncPeriodFails) {
  // Every 3rd SYNC: the wait for it is up to 30 ms, a bound assuming 1 ms
  // periods allows 3 ms.
  SyncLabConfig honest = at(1000, 3);
  SyncLabConfig wrong = honest;
  wrong.bound_sync_period_us = 1000;  // the SYNC comes every 10 ms, not every 1 ms
  const SyncResult good = sync_latency_scenario(line4(), honest, 150, nullptr, nullptr);
  const SyncResult bad = sync_latency_scenario(line4(), wrong, 150, nullptr, nullptr);
  EXPECT_TRUE(good.ok);
  // Same line, same presses, same measurements: only the bound differs.
  EXPECT_EQ(good.samples_ns, bad.samples_ns);
  EXPECT_LT(bad.bound.worst_ns, good.bound.worst_ns);
  EXPECT_GT(bad.outside, 0u);
  EXPECT_FALSE(bad.ok);
}

TEST(SyncLab, TheAnalysedSetHasTheSyncAndTheSynchronousPdo) {
  LineConfig c = line4();
  c.commission_more = [](int i, canopen::ObjectDictionary& od) {
    if (i == 0) {
      commission_write(od, 0x1006, 0, 10000, 4);
      commission_write(od, 0x1005, 0, 0x40000080u, 4);
    }
    if (i == 1) {
      commission_write(od, 0x1801, 1, 0x80000282u, 4);
      commission_write(od, 0x1801, 2, 4, 1);
      commission_write(od, 0x1801, 1, 0x282u, 4);
    }
  };
  Line line(c, nullptr);
  line.power_on_all();  // the set is read from the running gateways' dictionaries
  line.run_until(kNsPerS);
  std::vector<timing::MessageSpec> set;
  const Status listed = line_can_messages(line, 0, &set);
  ASSERT_TRUE(listed) << listed.message();
  const timing::MessageSpec* sync = find(set, 0x80);
  const timing::MessageSpec* pdo = find(set, 0x282);
  ASSERT_NE(sync, nullptr);
  ASSERT_NE(pdo, nullptr);
  EXPECT_EQ(sync->period_us, 10000u);
  EXPECT_EQ(sync->dlc, 0u);
  EXPECT_EQ(pdo->period_us, 40000u);  // every 4th SYNC
  EXPECT_EQ(&set.front(), sync);      // 80h wins arbitration against every PDO and heartbeat
}

TEST(Alternative, ArduinoControlledPathInsideItsBoundAndFasterThanThePc) {
  const AlternativeResult r = alternative_scenario(line4(), 500, 150, nullptr, nullptr);
  for (const LatencyResult* c : {&r.modbus, &r.canopen, &r.arduino}) {
    ASSERT_TRUE(c->bound.ok) << c->bound.error;
    EXPECT_EQ(c->samples_ns.size(), 150u);
    EXPECT_EQ(c->outside, 0u);
  }
  EXPECT_TRUE(r.ok);
  // No Modbus round in the loop: a tighter bound and a faster LED than the
  // PC-controlled path over the same two CAN hops.
  EXPECT_LT(r.arduino.bound.bound.worst_ns, r.canopen.bound.bound.worst_ns);
  EXPECT_LT(r.arduino.mean_ns, r.canopen.mean_ns);
  EXPECT_EQ(r.arduino.bound.params.can_up_worst_ns, r.canopen.bound.params.can_up_worst_ns);
}

}  // namespace
}  // namespace sim
}  // namespace mb2co
