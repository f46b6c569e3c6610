// Pacing of simulated time to the wall clock (hil/uno/pacer.h), with the
// wall clock as a plain number.
#include <gtest/gtest.h>

#include "pacer.h"

namespace mb2co {
namespace uno {
namespace {

TEST(Pacer, NeverLetsTheSimulationRunMoreThanItsLeadAhead) {
  static_assert(Pacer::kLeadUs == 2000, "the lead this test and docs/uno-sim.md state");
  Pacer p(true, 5000000, 0);
  EXPECT_EQ(p.allowed_sim_us(0, 5000000), Pacer::kLeadUs);
  EXPECT_EQ(p.allowed_sim_us(1000, 5000400), 2400u);
  EXPECT_EQ(p.wait_us(2400, 5000400), 2000u) << "wait until the wall reaches the simulation";
  EXPECT_EQ(p.wall_of(2400), 5002400u);
}

// mb2co-uno reads the clock once a pass (after the run) and, after a wait
// that timed out, takes the reading plus the timeout as the wall time: never
// later than the true one, so the lead holds, and the next reading catches
// up whatever the wake-up was late by.
TEST(Pacer, AWallTimeThatIsLateOnlyHoldsTheSimulationBack) {
  Pacer p(true, 0, 0);
  uint64_t sim = 0, read_us = 0;
  for (int pass = 0; pass < 1000; ++pass) {
    const uint64_t true_wall = read_us + p.wait_us(sim, read_us) + 300;  // woken 300 us late
    const uint64_t known = read_us + p.wait_us(sim, read_us);
    sim = p.allowed_sim_us(sim, known);
    ASSERT_LE(sim, true_wall + Pacer::kLeadUs) << "pass " << pass;
    read_us = true_wall + 200;  // the run took 200 us
  }
  EXPECT_GE(sim + Pacer::kLeadUs, read_us) << "kept pace: no more behind than one lead";
  EXPECT_EQ(p.jumps(), 0u);
}

TEST(Pacer, CountsHoldUpsAndTheSimulatedTimeTheyDropped) {
  static_assert(Pacer::kBehindUs == 20000, "the hold-up threshold this test and docs/uno-sim.md state");
  Pacer p(true, 0, 0);
  p.allowed_sim_us(10000, 25000);  // 15 ms behind: caught up, nothing dropped
  EXPECT_EQ(p.jumps(), 0u);
  EXPECT_EQ(p.dropped_us(), 0u);
  p.allowed_sim_us(10000, 60000);   // 50 ms behind: gone on from here
  p.allowed_sim_us(20000, 100000);  // 30 ms behind under the new mapping
  EXPECT_EQ(p.jumps(), 2u);
  EXPECT_EQ(p.dropped_us(), 50000u + 30000u);
}

TEST(Pacer, FallingFarBehindMovesTheMappingInsteadOfABurst) {
  Pacer p(true, 0, 0);
  EXPECT_EQ(p.allowed_sim_us(10000, 15000), 15000u + Pacer::kLeadUs) << "5 ms behind: catch up";
  EXPECT_EQ(p.allowed_sim_us(10000, 60000), 10000u + Pacer::kLeadUs) << "50 ms behind: go on from here";
  EXPECT_EQ(p.wall_of(10000), 60000u);
}

// What came in while held up arrives after where the simulation stood, in
// the order and proportion it came but within kReplayUs: spread over the
// whole hold-up (as until issue 25), it held back every frame that came
// after the move, and those then reached the chip back to back (overrun).
TEST(Pacer, WhatCameInWhileHeldUpArrivesSqueezedIntoTheReplayTime) {
  static_assert(Pacer::kReplayUs == 10000, "the replay time this test and docs/uno-sim.md state");
  Pacer p(true, 0, 0);
  EXPECT_EQ(p.sim_of(7000), 7000u) << "in step: the same time";
  p.allowed_sim_us(10000, 60000);  // held up at 10 ms for 50 ms: the mapping moves
  EXPECT_EQ(p.sim_of(9000), 9000u) << "came before the hold-up: as it came";
  EXPECT_EQ(p.sim_of(20000), 12000u) << "a fifth into the hold-up: a fifth into the 10 ms replay";
  EXPECT_EQ(p.sim_of(35000), 15000u) << "half way: half way, in order and proportion";
  EXPECT_EQ(p.sim_of(59000), 19800u) << "the end of the hold-up: by the end of the replay";
  EXPECT_EQ(p.sim_of(61000), 11000u) << "after the move: the new mapping";
}

// Behind by less than kBehindUs the mapping stays: a frame that came while
// the simulation was held up reaches it at the time it came, and so does
// the one after it, each in its place.
TEST(Pacer, CatchingUpKeepsEveryFrameAtItsOwnTime) {
  Pacer p(true, 0, 0);
  EXPECT_EQ(p.allowed_sim_us(10000, 25000), 25000u + Pacer::kLeadUs) << "15 ms behind: catch up";
  EXPECT_EQ(p.sim_of(20000), 20000u);
  EXPECT_EQ(p.sim_of(26000), 26000u);
  EXPECT_EQ(p.jumps(), 0u);
}

TEST(Pacer, ReportsASlowSimulationOnceWithItsRatio) {
  Pacer p(true, 0, 0);
  uint64_t sim = 0, wall = 0;
  std::string report;
  for (int i = 0; i < 3000 && report.empty(); ++i) {  // 0.5x real time
    wall += 2000;
    p.allowed_sim_us(sim, wall);
    sim += 1000;
    report = p.slow_report(sim, wall);
  }
  EXPECT_NE(report.find("(0.50x)"), std::string::npos) << report;
  for (int i = 0; i < 3000; ++i) {
    wall += 2000;
    p.allowed_sim_us(sim, wall);
    sim += 1000;
    EXPECT_EQ(p.slow_report(sim, wall), "") << "only once";
  }
}

TEST(Pacer, KeepingUpIsNotReported) {
  Pacer p(true, 0, 0);
  for (uint64_t t = 0; t < 3000000; t += 1000) {
    p.allowed_sim_us(t, t);
    EXPECT_EQ(p.slow_report(t, t), "");
  }
}

TEST(Pacer, UnpacedNeverWaits) {
  Pacer p(false, 0, 0);
  EXPECT_EQ(p.allowed_sim_us(5000000, 0), UINT64_MAX);
  EXPECT_EQ(p.wait_us(5000000, 0), 0u);
}

}  // namespace
}  // namespace uno
}  // namespace mb2co
