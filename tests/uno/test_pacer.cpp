// Pacing of simulated time to the wall clock (hil/uno/pacer.h), with the
// wall clock as a plain number.
#include <gtest/gtest.h>

#include "pacer.h"

namespace mb2co {
namespace uno {
namespace {

TEST(Pacer, NeverLetsTheSimulationRunMoreThan1msAhead) {
  Pacer p(true, 5000000, 0);
  EXPECT_EQ(p.allowed_sim_us(0, 5000000), Pacer::kLeadUs);
  EXPECT_EQ(p.allowed_sim_us(1000, 5000400), 1400u);
  EXPECT_EQ(p.wait_us(1400, 5000400), 1000u) << "wait until the wall reaches the simulation";
  EXPECT_EQ(p.wall_of(1400), 5001400u);
}

TEST(Pacer, FallingFarBehindMovesTheMappingInsteadOfABurst) {
  Pacer p(true, 0, 0);
  EXPECT_EQ(p.allowed_sim_us(10000, 15000), 16000u) << "5 ms behind: catch up";
  EXPECT_EQ(p.allowed_sim_us(10000, 60000), 11000u) << "50 ms behind: go on from here";
  EXPECT_EQ(p.wall_of(10000), 60000u);
}

TEST(Pacer, WhatCameInWhileHeldUpArrivesSpreadAsItCame) {
  Pacer p(true, 0, 0);
  EXPECT_EQ(p.sim_of(7000), 7000u) << "in step: the same time";
  p.allowed_sim_us(10000, 60000);  // held up at 10 ms for 50 ms: the mapping moves
  EXPECT_EQ(p.sim_of(30000), 30000u) << "came in while held up: 20 ms after where the simulation stood";
  EXPECT_EQ(p.sim_of(45000), 45000u) << "15 ms after the one before, as it came";
  EXPECT_EQ(p.sim_of(61000), 11000u) << "after the move: the new mapping";
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
