#include <gtest/gtest.h>

#include "fake_gateway.h"
#include "gateway/line_app.h"
#include "latency_cycle.h"
#include "latency_stats.h"

using namespace mb2co;
using namespace mb2co::pcapp;

namespace {
struct LatencyTest : ::testing::Test {
  FakeGateway gw;
  LatencyCycle lab{gw.layout, false, gateway::kStart, 2};
  void cycle() { lab.step(gw.in, gw.out); }
  /// The firmware's side of a press: edge at `edge_us`, LED on at `led_us`.
  void press(uint32_t edge_us, uint32_t led_us) {
    gw.set(Field::kInputs, gateway::kStart);
    gw.set(Field::kEdgeUs, edge_us);
    cycle();
    EXPECT_EQ(gw.written(Field::kLabLed), 1u);
    gw.set(Field::kLedUs, led_us);
    gw.set(Field::kLeds, gateway::kLedLab);
    cycle();
  }
  void release(uint32_t at_us) {
    gw.set(Field::kInputs, 0);
    gw.set(Field::kEdgeUs, at_us);
    cycle();
    EXPECT_EQ(gw.written(Field::kLabLed), 0u);
    gw.set(Field::kLedUs, at_us + 5000);
    gw.set(Field::kLeds, 0);
    cycle();
  }
};
}  // namespace

TEST_F(LatencyTest, DelayFromTheFirmwareStampsPerPress) {
  cycle();
  press(1000000, 1031000);
  EXPECT_EQ(lab.take_event(), "press 1 delay_us=31000");
  release(1200000);
  EXPECT_TRUE(lab.take_event().empty());  // releases are not measured
  EXPECT_FALSE(lab.done());
  press(0xFFFFF000u, 0x00004000u);  // across the 32-bit wrap of micros()
  ASSERT_EQ(lab.records().size(), 2u);
  EXPECT_EQ(lab.records()[1].delay_us, 0x5000u);
  EXPECT_TRUE(lab.done());
  EXPECT_EQ(lab.csv(),
            "press,cycle,edge_us,led_us,delay_us\n1,3,1000000,1031000,31000\n"
            "2,7,4294963200,16384,20480\n");
}

TEST_F(LatencyTest, PressGoneBeforeTheLedWasReadIsMissedNotMismeasured) {
  cycle();
  gw.set(Field::kInputs, gateway::kStart);
  gw.set(Field::kEdgeUs, 1000);
  cycle();
  gw.set(Field::kLedUs, 9000);  // the LED went on and off again in between
  gw.set(Field::kLeds, 0);
  gw.set(Field::kInputs, 0);
  cycle();
  EXPECT_EQ(lab.records().size(), 0u);
  EXPECT_EQ(lab.missed(), 1u);
}

TEST_F(LatencyTest, RemoteMeasuresFromTheRemoteEdgeOnTheCommonClock) {
  // 100 ppm, 1 ms spread; both clocks set 400 ms before the LED.
  ClockBound bound;
  bound.spread_us = 1000;
  bound.drift_ppm = 100;
  LatencyCycle remote(gw.layout, true, gateway::kStop2, 0, bound);
  EXPECT_EQ(remote.required_reads()[0], Field::kRemoteButtons);
  remote.step(gw.in, gw.out);
  gw.set(Field::kRemoteButtons, gateway::kStop2);
  gw.set(Field::kRemoteUs, 1030000);  // the PDO's arrival here
  gw.set(Field::kEdgeUs, 1);          // the local panel's stamp: not used
  remote.step(gw.in, gw.out);
  ASSERT_TRUE(remote.wants_remote_edge()) << "the press is seen, its remote edge not yet read";
  RemoteEdge e;
  e.edge_us = 1000000;  // the remote station's own stamp, common clock
  e.set_here_us = 1040000 - 400000;
  e.set_remote_us = 1040000 - 400000;
  remote.set_remote_edge(e);
  EXPECT_FALSE(remote.wants_remote_edge());
  gw.set(Field::kLedUs, 1040000);
  gw.set(Field::kLeds, gateway::kLedLab);
  remote.step(gw.in, gw.out);
  ASSERT_EQ(remote.records().size(), 1u);
  const PressRecord& r = remote.records()[0];
  EXPECT_EQ(r.delay_us, 40000u) << "from the remote edge, not from the PDO's arrival";
  EXPECT_EQ(r.hop_us, 30000u) << "edge to the PDO's arrival: debounce, TPDO, CAN";
  EXPECT_EQ(r.uncertainty_us, 1000u + 76u)
      << "spread + 100 ppm of 400 ms here and 360 ms there (at its edge)";
  EXPECT_EQ(remote.take_event(), "press 1 delay_us=40000 +-1076 hop_us=30000");
  EXPECT_NE(remote.summary().find("clock=common(TIME) uncertainty_us<=1076"), std::string::npos);
}

TEST_F(LatencyTest, RemotePressWhoseEdgeWasNotReadIsMissedNotMismeasured) {
  LatencyCycle remote(gw.layout, true, gateway::kStart, 0);
  remote.step(gw.in, gw.out);
  gw.set(Field::kRemoteButtons, gateway::kStart);
  gw.set(Field::kRemoteUs, 500);
  remote.step(gw.in, gw.out);
  gw.set(Field::kLedUs, 2500);
  gw.set(Field::kLeds, gateway::kLedLab);
  remote.step(gw.in, gw.out);  // the LED came before the edge was read
  EXPECT_TRUE(remote.records().empty());
  EXPECT_EQ(remote.missed(), 1u);
  gw.set(Field::kRemoteButtons, 0);
  remote.step(gw.in, gw.out);
  gw.set(Field::kRemoteButtons, gateway::kStart);
  remote.step(gw.in, gw.out);
  remote.remote_edge_lost();  // the remote station did not answer
  EXPECT_FALSE(remote.wants_remote_edge());
  EXPECT_EQ(remote.missed(), 2u);
}

TEST(ClockUncertainty, AStampsAgeIsFromTheLastSetBeforeIt) {
  EXPECT_EQ(clock_age_us(5000, 1000, 800), 4000u);
  EXPECT_EQ(clock_age_us(5000, 6000, 4800), 200u) << "a TIME frame after the stamp, read with it";
  EXPECT_EQ(clock_age_us(10, 0xFFFFFF00u, 0xFFFFFE00u), 266u) << "across the 2^32 wrap";
}

TEST(ClockUncertainty, SpreadPlusDriftOfBothAgesRoundedUp) {
  ClockBound b;
  b.spread_us = 1000;
  b.drift_ppm = 100;
  EXPECT_EQ(clock_uncertainty_us(b, 0, 0), 1000u);
  EXPECT_EQ(clock_uncertainty_us(b, 1000000, 1000000), 1200u) << "100 ppm of 2 s";
  EXPECT_EQ(clock_uncertainty_us(b, 1, 0), 1001u) << "rounded up";
  b.drift_ppm = 0;
  EXPECT_EQ(clock_uncertainty_us(b, 4000000000u, 4000000000u), 1000u) << "clocks of one host";
}

TEST(LatencyStats, FiguresAndPercentile) {
  LatencyStats s;
  for (uint32_t v = 1; v <= 100; ++v) s.add(v * 1000);
  EXPECT_EQ(s.min_us(), 1000u);
  EXPECT_EQ(s.max_us(), 100000u);
  EXPECT_EQ(s.mean_us(), 50500u);
  EXPECT_EQ(s.percentile_us(99), 99000u);
  EXPECT_EQ(s.percentile_us(100), 100000u);
  EXPECT_EQ(s.percentile_us(1), 1000u);
}

TEST(LatencyStats, HistogramBinsAreOneTwoFiveSteps) {
  LatencyStats s;
  s.add(20000);
  s.add(21000);
  s.add(21500);
  s.add(29000);
  EXPECT_EQ(s.bin_width_us(12), 1000u);  // span 9001 us -> 10 bins of 1 ms
  EXPECT_EQ(s.bin_width_us(4), 5000u);
  const std::string r = s.report(12);
  EXPECT_NE(r.find("presses 4  min 20.000 ms  mean 22.875 ms  p99 29.000 ms  max 29.000 ms"),
            std::string::npos);
  EXPECT_NE(r.find("[  21.000,   22.000) ms      2  ########################################"),
            std::string::npos);
  EXPECT_NE(r.find("[  29.000,   30.000) ms      1  ####################\n"), std::string::npos);
}

TEST(LatencyStats, EmptyReport) {
  EXPECT_EQ(LatencyStats().report(), "no presses measured\n");
}
