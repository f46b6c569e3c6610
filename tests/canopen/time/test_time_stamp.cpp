// TIME (CiA 301 §7.2.6, 1012h) and the high-resolution time stamp 1013h:
// black box through frames and SDO, on the host profile (consumer and
// producer). The node is handed its local clock (h.now); the network clock
// is 1013h (µs since 1984-01-01, mod 2^32).
#include <gtest/gtest.h>

#include "canopen/time_stamp.h"
#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
/// 1012h's default is 100h with neither bit (as CANopenNode's example OD):
/// a node consumes TIME once a tool sets the consumer bit, as this fixture
/// does first (the default itself: DefaultIs100hWithNeitherBit).
class Time : public IoNodeTest {
 protected:
  void SetUp() override {
    IoNodeTest::SetUp();
    ASSERT_EQ(h.write_u32(0x1012, 0, 0x80000100u), 0u);
    bus.frames.clear();
  }
};
using TimeDefault = IoNodeTest;

/// A TIME frame on 100h: `ms` after midnight of day `days`.
CanFrame time_frame(uint32_t ms, uint16_t days, uint8_t dlc = 6) {
  uint8_t b[6];
  encode_time_of_day(TimeOfDay{ms, days}, b);
  CanFrame f = {};
  f.id = 0x100;
  f.dlc = dlc;
  for (uint8_t i = 0; i < 6; ++i) f.data[i] = b[i];
  return f;
}

// 2026-01-01 is day 15,341 after 1984-01-01; 12:00:00.250.
const uint16_t kDay = 15341;
const uint32_t kNoonMs = 43200250;
const uint32_t kNoonUs =
    static_cast<uint32_t>((uint64_t{kDay} * 86400000000ull + uint64_t{kNoonMs} * 1000u) & 0xFFFFFFFFu);

TEST(TimeOfDayCodec, FrameBytesAreMsThenDaysLittleEndianWithTheTopFourBitsClear) {
  uint8_t b[6];
  encode_time_of_day(TimeOfDay{0x0ABCDEF1u, 0x1234}, b);
  EXPECT_EQ(Bytes(b, b + 6), Bytes({0xF1, 0xDE, 0xBC, 0x0A, 0x34, 0x12}));
  encode_time_of_day(TimeOfDay{0xFFFFFFFFu, 0}, b);
  EXPECT_EQ(b[3], 0x0F) << "28 bits of ms; bits 28-31 reserved (0)";
  const uint8_t in[6] = {0xF1, 0xDE, 0xBC, 0xFA, 0x34, 0x12};
  const TimeOfDay t = decode_time_of_day(in);
  EXPECT_EQ(t.ms, 0x0ABCDEF1u) << "reserved bits masked as CANopenNode does";
  EXPECT_EQ(t.days, 0x1234u);
}

TEST(TimeOfDayCodec, NetworkMicrosecondsAreSinceTheEpochModuloTwoToThe32) {
  EXPECT_EQ(network_us_of(TimeOfDay{kNoonMs, kDay}), kNoonUs);
  // Midnight is no discontinuity: the last ms of a day and the first of the next are 1 ms apart.
  EXPECT_EQ(network_us_of(TimeOfDay{0, kDay + 1}) - network_us_of(TimeOfDay{kMsPerDay - 1, kDay}), 1000u);
}

TEST_F(TimeDefault, DefaultIs100hWithNeitherBitAsCanopenNodesExampleOd) {
  EXPECT_EQ(h.read(0x1012, 0), 0x00000100u);
  EXPECT_FALSE(io.node().time().clock_set());
  h.rx(time_frame(kNoonMs, kDay));
  EXPECT_FALSE(io.node().time().clock_set()) << "not a consumer until 1012h bit 31 is set";
}

TEST_F(Time, ConsumerSetsTheClockTo1013hAtTheFramesArrival) {
  h.now = 5000000;
  h.rx(time_frame(kNoonMs, kDay));
  EXPECT_TRUE(io.node().time().clock_set());
  EXPECT_EQ(io.node().time().offset_us(), kNoonUs - 5000000u);
  h.advance_us(1234567);
  // Read by SDO 10 ms later: the network time of the request.
  h.now += 10000;
  EXPECT_EQ(h.read(0x1013, 0), kNoonUs + 1234567u + 10000u);
  EXPECT_EQ(io.node().time().network_us(h.now), kNoonUs + 1244567u);
}

TEST_F(Time, ConsumerRunsAcrossTheLocalClocksWrap) {
  h.now = 0xFFFFF000u;
  h.rx(time_frame(kNoonMs, kDay));
  h.run_us(0x2000, 0x800);  // through local 0
  EXPECT_EQ(h.read(0x1013, 0), kNoonUs + 0x2000u);
}

TEST_F(Time, OnlySixByteFramesInPreOrOperationalSetTheClock) {
  h.rx(time_frame(kNoonMs, kDay, 5));
  h.rx(time_frame(kNoonMs, kDay, 8));
  EXPECT_FALSE(io.node().time().clock_set()) << "CO_TIME.c: DLC must be 6, others are ignored (no EMCY)";
  EXPECT_EQ(h.take(), Frames({}));
  h.nmt(0x02, kId);  // stopped
  h.rx(time_frame(kNoonMs, kDay));
  EXPECT_FALSE(io.node().time().clock_set()) << "consumed in pre-operational and operational only";
  h.nmt(0x01, kId);
  h.rx(time_frame(kNoonMs, kDay));
  EXPECT_TRUE(io.node().time().clock_set());
}

TEST_F(Time, ConsumerBitClearOrAnotherIdIgnoresTheFrame) {
  EXPECT_EQ(h.write_u32(0x1012, 0, 0x00000100u), 0u);
  h.rx(time_frame(kNoonMs, kDay));
  EXPECT_FALSE(io.node().time().clock_set());
  EXPECT_EQ(h.write_u32(0x1012, 0, 0x800001F0u), 0u);
  h.rx(time_frame(kNoonMs, kDay));
  EXPECT_FALSE(io.node().time().clock_set()) << "on 100h, consuming 1F0h";
  CanFrame f = time_frame(kNoonMs, kDay);
  f.id = 0x1F0;
  h.rx(f);
  EXPECT_TRUE(io.node().time().clock_set());
}

TEST_F(Time, CobIdWritesRefuseExtendedAndRestrictedIds) {
  EXPECT_EQ(h.write_u32(0x1012, 0, 0xA0000100u), kAbortInvalidValue) << "bit 29: 29-bit ids";
  EXPECT_EQ(h.write_u32(0x1012, 0, 0x80000701u), kAbortInvalidValue) << "restricted (heartbeat range)";
  EXPECT_EQ(h.read(0x1012, 0), 0x80000100u);
}

TEST_F(Time, AcceptanceHasTheTimeIdWhileConsuming) {
  auto has = [&](uint16_t id) {
    CanIdRange r[kMaxAcceptanceRanges];
    const uint8_t n = io.node().acceptance(r);
    for (uint8_t i = 0; i < n; ++i) {
      if (r[i].mask == kCanRangeExact && r[i].id == id) return true;
    }
    return false;
  };
  EXPECT_TRUE(has(0x100));
  EXPECT_EQ(h.write_u32(0x1012, 0, 0x00000100u), 0u);
  EXPECT_FALSE(has(0x100));
}

TEST_F(Time, A1013hWriteSetsTheClockAtTheRequestsArrival) {
  h.now = 777;
  EXPECT_EQ(h.write_u32(0x1013, 0, 0x12345678u), 0u);
  EXPECT_TRUE(io.node().time().clock_set());
  h.advance_us(1000);
  EXPECT_EQ(h.read(0x1013, 0), 0x12345678u + 1000u);
}

TEST_F(Time, ProducerSendsTimeOfDayEveryPeriod) {
  io.node().time().set_time_of_day(TimeOfDay{kMsPerDay - 500, kDay}, h.now);
  EXPECT_EQ(h.write_u32(0x1012, 0, 0x40000100u), 0u);
  h.advance_us(0);
  uint8_t b[6];
  encode_time_of_day(TimeOfDay{kMsPerDay - 500, kDay}, b);
  EXPECT_EQ(h.take(), Frames({to_string(F(0x100, {b[0], b[1], b[2], b[3], b[4], b[5]}))}));
  h.run_us(999000, 1000);
  EXPECT_EQ(h.take(), Frames({})) << "period 1000 ms";
  uint32_t at = 0;
  ASSERT_TRUE(io.node().next_deadline(h.now, &at));
  EXPECT_EQ(at, h.now + 1000u);
  h.advance_us(1000);
  encode_time_of_day(TimeOfDay{500, kDay + 1}, b);  // over midnight
  EXPECT_EQ(h.take(), Frames({to_string(F(0x100, {b[0], b[1], b[2], b[3], b[4], b[5]}))}));
}

TEST_F(Time, ResetCommunicationUnsetsTheClock) {
  h.rx(time_frame(kNoonMs, kDay));
  h.nmt(0x82, kId);
  EXPECT_FALSE(io.node().time().clock_set());
  EXPECT_EQ(io.node().time().offset_us(), 0u);
  EXPECT_EQ(h.read(0x1012, 0), 0x00000100u) << "the default again (unless saved)";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
