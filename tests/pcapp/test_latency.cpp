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

TEST_F(LatencyTest, RemoteUsesThePdoArrival) {
  LatencyCycle remote(gw.layout, true, gateway::kStop2, 0);
  EXPECT_EQ(remote.required_reads()[0], Field::kRemoteButtons);
  remote.step(gw.in, gw.out);
  gw.set(Field::kRemoteButtons, gateway::kStop2);
  gw.set(Field::kRemoteUs, 500);
  gw.set(Field::kEdgeUs, 1);  // the local panel's stamp: not used
  remote.step(gw.in, gw.out);
  gw.set(Field::kLedUs, 2500);
  gw.set(Field::kLeds, gateway::kLedLab);
  remote.step(gw.in, gw.out);
  ASSERT_EQ(remote.records().size(), 1u);
  EXPECT_EQ(remote.records()[0].delay_us, 2000u);
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
