// The line's CANopen configuration as a message set.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "timing/line_config.h"

namespace mb2co {
namespace timing {
namespace {

std::vector<MessageSpec> build(const LineCanConfig& cfg, LineStatus expected = LineStatus::kOk) {
  std::vector<MessageSpec> out(line_message_count(cfg) + 1);
  size_t n = 0;
  EXPECT_EQ(build_line_messages(cfg, out.data(), out.size(), &n), expected);
  out.resize(n);
  return out;
}

TEST(LineConfig, DefaultsGiveTpdo1AndHeartbeatPerStation) {
  const LineCanConfig cfg;
  const auto set = build(cfg);
  ASSERT_EQ(set.size(), 6u);  // 3 stations x (TPDO1 + heartbeat)
  EXPECT_STREQ(set[0].name, "TPDO1.1");
  EXPECT_EQ(set[0].id, 0x181u);
  EXPECT_EQ(set[0].dlc, 3);             // the gateway's TPDO1: RUN state + STOP2 counter
  EXPECT_EQ(set[0].period_us, 10000u);  // inhibit 100 x 100 µs = T
  EXPECT_EQ(set[0].deadline_us, 10000u);
  EXPECT_STREQ(set[5].name, "HB.3");
  EXPECT_EQ(set[5].id, 0x703u);
  EXPECT_EQ(set[5].period_us, 100000u);  // 1017h = 100 ms, as the gateway
}

TEST(LineConfig, SeedFiveNodeSyncExample) {
  LineCanConfig cfg;
  cfg.stations = 5;
  cfg.bitrate_bps = 100000;
  cfg.tpdo1 = false;
  cfg.heartbeat_ms = 0;
  cfg.sync_period_us = 100000;
  cfg.sync_tpdos = 2;
  cfg.sync_tpdo_dlc = 8;
  const auto set = build(cfg);
  ASSERT_EQ(set.size(), 11u);
  EXPECT_STREQ(set[0].name, "SYNC");
  EXPECT_EQ(set[0].id, 0x80u);
  EXPECT_STREQ(set[1].name, "TPDO2.1");
  EXPECT_EQ(set[1].id, 0x281u);
  EXPECT_STREQ(set[10].name, "TPDO3.5");
  EXPECT_EQ(set[10].id, 0x385u);
  // SYNC stuffed by the course bound (54) + 10 x 130; the seed's 1347 counts
  // the SYNC unstuffed (see test_load.cpp).
  EXPECT_EQ(window_bits(set.data(), set.size(), 100000, 100000, WorstCase::kCourse), 1354u);
}

TEST(LineConfig, SyncTransmissionTypeMultipliesThePeriod) {
  LineCanConfig cfg;
  cfg.stations = 1;
  cfg.sync_period_us = 2500;
  cfg.sync_tpdos = 1;
  cfg.sync_transmission_type = 4;
  cfg.queue_jitter_us = 300;
  const auto set = build(cfg);
  ASSERT_EQ(set.size(), 4u);  // SYNC, TPDO1.1, TPDO2.1, HB.1
  EXPECT_EQ(set[2].period_us, 10000u);
  EXPECT_EQ(set[2].jitter_us, 300u);
}

TEST(LineConfig, InvalidConfigurations) {
  LineCanConfig cfg;
  cfg.stations = 0;
  build(cfg, LineStatus::kStations);
  cfg = LineCanConfig{};
  cfg.tpdo1_inhibit_100us = 0;
  build(cfg, LineStatus::kNoInterArrival);
  cfg = LineCanConfig{};
  cfg.tpdo1_event_timer_ms = 5;  // shorter than the 10 ms inhibit time
  build(cfg, LineStatus::kEventTimer);
  cfg = LineCanConfig{};
  cfg.sync_tpdos = 1;  // without SYNC
  build(cfg, LineStatus::kSyncTpdos);
  cfg = LineCanConfig{};
  cfg.bitrate_bps = 2000000;
  build(cfg, LineStatus::kBitrate);
  cfg = LineCanConfig{};
  std::vector<MessageSpec> small(2);
  size_t n = 0;
  EXPECT_EQ(build_line_messages(cfg, small.data(), small.size(), &n), LineStatus::kCapacity);
  EXPECT_EQ(n, 0u);
}

TEST(LineConfig, HundredTwentySevenStationsNamesAndIds) {
  LineCanConfig cfg;
  cfg.stations = 127;
  const auto set = build(cfg);
  ASSERT_EQ(set.size(), 254u);
  EXPECT_STREQ(set[126].name, "TPDO1.127");
  EXPECT_EQ(set[126].id, 0x1FFu);
  EXPECT_EQ(set[253].id, 0x77Fu);
}

}  // namespace
}  // namespace timing
}  // namespace mb2co
