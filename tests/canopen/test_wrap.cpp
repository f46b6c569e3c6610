// The 32-bit microsecond clock wraps every ~71.6 minutes (Arduino micros()):
// every timed service runs across the wrap exactly as anywhere else.
#include <gtest/gtest.h>

#include <map>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

class Wrap : public ::testing::Test {
 protected:
  static constexpr uint8_t kId = 3;
  static constexpr uint32_t kStart = 0xFFFFFFFFu - 250000u;  // 250 ms before the wrap
  void SetUp() override {
    h.now = kStart;
    io.start(kId, h.now);
    bus.frames.clear();
  }
  FrameLog bus;
  ionode::IoNode io{bus.sink()};
  Harness h{io.node(), bus};
};

TEST_F(Wrap, PeriodicServicesKeepTheirPeriodAcrossTheWrap) {
  ASSERT_EQ(h.write_u16(0x1017, 0, 100), 0u);     // heartbeat 100 ms
  ASSERT_EQ(h.write_u32(0x1006, 0, 30000u), 0u);  // SYNC 30 ms
  ASSERT_EQ(h.write_u32(0x1005, 0, 0x40000080u), 0u);
  ASSERT_EQ(h.write_u16(0x1800, 5, 70), 0u);  // TPDO1 event timer 70 ms
  h.nmt(0x01, kId);
  h.take();
  std::map<uint32_t, std::vector<uint32_t>> sent;  // id -> times (µs, modulo 2^32)
  for (int i = 0; i < 6000; ++i) {                 // 600 ms, across the wrap
    h.advance_us(100);
    for (const CanFrame& f : h.take_frames()) sent[f.id].push_back(h.now);
  }
  auto check = [&](uint32_t id, uint32_t period_us, size_t at_least) {
    const std::vector<uint32_t>& t = sent[id];
    ASSERT_GE(t.size(), at_least) << std::hex << id;
    bool crossed = false;
    for (size_t k = 1; k < t.size(); ++k) {
      EXPECT_EQ(t[k] - t[k - 1], period_us) << std::hex << id << " at " << t[k];
      crossed = crossed || t[k] < t[k - 1];
    }
    EXPECT_TRUE(crossed) << "the series crossed the wrap";
  };
  check(0x703, 100000, 5);
  check(0x080, 30000, 19);
  check(0x183, 70000, 8);
}

TEST_F(Wrap, TimeoutsFireOnTimeAcrossTheWrap) {
  // SDO server timeout (1 s): start 250 ms before the wrap.
  EXPECT_EQ(to_string(h.sdo({0x40, 0x08, 0x10, 0x00})), "<583> 41 08 10 00 0E 00 00 00");
  const uint32_t t0 = h.now;
  h.run_us(999000, 1000);
  EXPECT_EQ(h.take(), Frames({})) << "not early (a naive compare would fire at the wrap)";
  h.advance_us(1000);
  EXPECT_EQ(h.take(), Frames({abort_frame(kId, 0x1008, 0, kAbortTimeout)}));
  EXPECT_EQ(h.now - t0, 1000000u);
  EXPECT_LT(h.now, t0) << "the deadline was beyond the wrap";
}

TEST_F(Wrap, HeartbeatConsumerAndRpdoTimeoutAcrossTheWrap) {
  ASSERT_EQ(h.write_u32(0x1016, 1, 0x000501F4u), 0u);  // node 5, 500 ms
  ASSERT_EQ(h.write_u16(0x1400, 5, 400), 0u);          // RPDO1 400 ms
  h.nmt(0x01, kId);
  h.take();
  h.rx(F(0x705, {0x05}));
  h.rx(F(0x203, {0x00, 0x00}));
  h.run_us(399000, 1000);
  EXPECT_EQ(h.take(), Frames({}));
  h.advance_us(1000);
  EXPECT_EQ(h.take(), Frames({"<083> 50 82 11 00 00 00 00 00"}));
  h.run_us(99000, 1000);
  EXPECT_EQ(h.take(), Frames({}));
  h.advance_us(1000);
  EXPECT_EQ(io.node().heartbeat_consumer().remote_state(5), kHbTimeout);
}

TEST_F(Wrap, InhibitTimesAcrossTheWrap) {
  h.now = 0xFFFFFFFFu - 2000u;
  ASSERT_EQ(h.write_u16(0x1015, 0, 50), 0u);  // EMCY 5 ms
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  ASSERT_EQ(h.write_u16(0x1800, 3, 30), 0u);  // TPDO 3 ms
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x183u), 0u);
  h.nmt(0x01, kId);
  EXPECT_EQ(h.take(), Frames({"<183> 00 00"}));
  const uint32_t t0 = h.now;
  io.set_input(0, 1);
  io.node().emcy().raise(0x1000, kErrGeneric);
  io.node().emcy().raise(0x2000, kErrGeneric);
  std::vector<std::pair<uint32_t, std::string>> log;
  for (int i = 0; i < 8000; ++i) {
    h.advance_us(1);
    for (const CanFrame& f : h.take_frames()) log.emplace_back(h.now - t0, to_string(f));
  }
  ASSERT_EQ(log.size(), 3u);
  EXPECT_EQ(log[0], std::make_pair(1u, std::string("<083> 00 10 01 00 00 00 00 00")));
  EXPECT_EQ(log[1], std::make_pair(3000u, std::string("<183> 01 00")));
  EXPECT_EQ(log[2], std::make_pair(5001u, std::string("<083> 00 20 01 00 00 00 00 00")));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
