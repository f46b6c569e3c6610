// RTU framing by character timestamps: t3.5 ends a frame, t1.5 inside a frame
// invalidates it, CRC/length/overrun errors are counted and never answered.
#include <gtest/gtest.h>

#include "modbus/master_codec.h"
#include "support/slave_harness.h"

namespace mb2co {
namespace modbus {
namespace test {
namespace {

TEST(ModbusFraming, FrameEndsExactlyAfterT35OfSilence) {
  SlaveHarness h;
  h.feed(read_holding(0, 1), h.timing.t35_us);
  h.wait(h.timing.t35_us - 1);
  EXPECT_TRUE(h.responses.empty()) << "answered before t3.5 of silence";
  uint32_t deadline = 0;
  ASSERT_TRUE(h.slave.deadline(deadline));
  EXPECT_EQ(deadline, h.now_us + 1);
  h.wait(1);
  ASSERT_EQ(h.responses.size(), 1u);
  EXPECT_EQ(h.responses[0], with_crc({kSlaveAddress, 0x03, 0x02, 0x00, 0x00}));
  EXPECT_FALSE(h.slave.deadline(deadline)) << "idle line has no deadline";
}

// next_deadline (the form Node and Gateway share): the end of the frame in
// progress; process() before it changes nothing, at it the frame is answered.
TEST(ModbusFraming, NextDeadlineIsTheFrameEndAndNothingHappensBeforeIt) {
  SlaveHarness h;
  uint32_t at = 0;
  EXPECT_FALSE(h.slave.next_deadline(h.now_us, &at)) << "an idle line waits only for characters";
  h.feed(read_holding(0, 1), h.timing.t35_us);
  ASSERT_TRUE(h.slave.next_deadline(h.now_us, &at));
  EXPECT_EQ(at, h.now_us + h.timing.t35_us);
  h.wait(at - 1u - h.now_us);
  EXPECT_TRUE(h.responses.empty());
  EXPECT_EQ(h.slave.counters().bus_messages, 0u) << "the frame is not closed before t3.5";
  ASSERT_TRUE(h.slave.next_deadline(h.now_us, &at));
  EXPECT_EQ(at, h.now_us + 1u) << "the deadline stays";
  h.wait(1);
  EXPECT_EQ(h.responses.size(), 1u);
  EXPECT_FALSE(h.slave.next_deadline(h.now_us, &at));
}

TEST(ModbusFraming, NextDeadlineEndsThePowerUpWait) {
  SlaveHarness h;
  h.slave.begin(h.now_us);
  uint32_t at = 0;
  ASSERT_TRUE(h.slave.next_deadline(h.now_us, &at));
  EXPECT_EQ(at, h.now_us + h.timing.t35_us);
  h.wait(h.timing.t35_us);
  EXPECT_FALSE(h.slave.next_deadline(h.now_us, &at)) << "the line was quiet: idle";
}

TEST(ModbusFraming, SilenceUpToT15InsideAFrameIsAccepted) {
  SlaveHarness h;
  const Bytes adu = write_register(5, 0x1234);
  h.feed(Bytes(adu.begin(), adu.begin() + 3), h.timing.t35_us);
  h.feed(Bytes(adu.begin() + 3, adu.end()), h.timing.t15_us);
  h.wait(h.timing.t35_us);
  ASSERT_EQ(h.responses.size(), 1u);
  EXPECT_EQ(h.bank.holding_registers[5], 0x1234);
  EXPECT_EQ(h.slave.counters().bus_comm_errors, 0u);
}

TEST(ModbusFraming, SilenceAboveT15InsideAFrameDiscardsIt) {
  SlaveHarness h;
  const Bytes adu = write_register(5, 0x1234);
  h.feed(Bytes(adu.begin(), adu.begin() + 3), h.timing.t35_us);
  h.feed(Bytes(adu.begin() + 3, adu.end()), h.timing.t15_us + 1);
  h.wait(h.timing.t35_us);
  EXPECT_TRUE(h.responses.empty());
  EXPECT_EQ(h.bank.holding_registers[5], 0);
  EXPECT_EQ(h.slave.counters().bus_comm_errors, 1u);
  EXPECT_EQ(h.slave.counters().bus_messages, 0u);
  EXPECT_EQ(h.slave.stats().t15_violations, 1u);
  // The line recovers: the next frame is served.
  EXPECT_FALSE(h.transact(read_holding(5, 1)).empty());
}

TEST(ModbusFraming, T15CheckCanBeDisabledForJitteryPorts) {
  SlaveHarness h;
  h.slave.set_check_t15(false);
  const Bytes adu = write_register(5, 0x1234);
  h.feed(Bytes(adu.begin(), adu.begin() + 3), h.timing.t35_us);
  h.feed(Bytes(adu.begin() + 3, adu.end()), h.timing.t35_us - 1);
  h.wait(h.timing.t35_us);
  EXPECT_EQ(h.responses.size(), 1u);
  EXPECT_EQ(h.bank.holding_registers[5], 0x1234);
}

TEST(ModbusFraming, FrameSplitByT35GapIsTwoBadFrames) {
  SlaveHarness h;
  const Bytes adu = write_register(5, 0x1234);
  h.feed(Bytes(adu.begin(), adu.begin() + 4), h.timing.t35_us);
  // No process() call in between: the gap is seen from the stamps alone.
  h.feed(Bytes(adu.begin() + 4, adu.end()), h.timing.t35_us);
  h.wait(h.timing.t35_us);
  EXPECT_TRUE(h.responses.empty());
  EXPECT_EQ(h.bank.holding_registers[5], 0);
  EXPECT_EQ(h.slave.counters().bus_comm_errors, 2u);  // 4 bytes bad CRC, 4 bytes bad CRC
  EXPECT_EQ(h.bank.data_calls, 0u);
}

TEST(ModbusFraming, BadCrcIgnoredAndCounted) {
  SlaveHarness h;
  Bytes adu = write_register(5, 0x1234);
  adu.back() ^= 0x01;
  EXPECT_TRUE(h.transact(adu).empty());
  EXPECT_EQ(h.slave.counters().bus_comm_errors, 1u);
  EXPECT_EQ(h.slave.counters().bus_messages, 0u);
  EXPECT_EQ(h.slave.counters().server_messages, 0u);
  EXPECT_EQ(h.bank.data_calls, 0u);
}

TEST(ModbusFraming, TooShortFrameCounted) {
  SlaveHarness h;
  EXPECT_TRUE(h.transact({kSlaveAddress, 0x03, 0x00}).empty());
  EXPECT_EQ(h.slave.counters().bus_comm_errors, 1u);
}

TEST(ModbusFraming, CharacterErrorInvalidatesFrame) {
  SlaveHarness h;
  const Bytes adu = write_register(5, 0x1234);
  h.feed(adu, h.timing.t35_us);
  h.now_us += h.timing.char_us;
  h.slave.on_char_error(h.now_us);
  h.wait(h.timing.t35_us);
  EXPECT_TRUE(h.responses.empty());
  EXPECT_EQ(h.bank.holding_registers[5], 0);
  EXPECT_EQ(h.slave.counters().bus_comm_errors, 1u);
}

TEST(ModbusFraming, OverlongFrameIsAnOverrun) {
  SlaveHarness h;
  Bytes junk(300, 0x55);
  junk[0] = kSlaveAddress;
  EXPECT_TRUE(h.transact(junk).empty());
  EXPECT_EQ(h.slave.counters().char_overruns, 1u);
  EXPECT_EQ(h.slave.counters().bus_comm_errors, 0u);
  EXPECT_FALSE(h.transact(read_holding(0, 1)).empty());
}

TEST(ModbusFraming, ExactlyMaximumFrameAccepted) {
  SlaveHarness h;
  // FC 10 with 123 registers is the longest request: 9 + 246 = 255 bytes
  // (written above the read-only and limited registers of the test layout).
  std::vector<uint16_t> values(123, 7);
  Bytes adu(256);
  adu.resize(build_write_registers(adu.data(), 256, kSlaveAddress, 120, 123, values.data()));
  ASSERT_EQ(adu.size(), 255u);
  EXPECT_FALSE(h.transact(adu).empty());
  EXPECT_EQ(h.bank.holding_registers[120 + 122], 7);
}

TEST(ModbusFraming, OtherSlavesFramesCountedOnBusOnly) {
  SlaveHarness h;
  EXPECT_TRUE(h.transact(write_register(5, 9, 2)).empty());
  EXPECT_TRUE(h.transact(write_register(5, 9, 248)).empty());  // reserved address
  EXPECT_EQ(h.bank.holding_registers[5], 0);
  EXPECT_EQ(h.slave.counters().bus_messages, 2u);
  EXPECT_EQ(h.slave.counters().server_messages, 0u);
}

TEST(ModbusFraming, LateProcessStillAnswersWhenNextFrameStarts) {
  SlaveHarness h;
  h.feed(write_register(1, 11), h.timing.t35_us);
  h.feed(write_register(2, 22), h.timing.t35_us);  // first frame ends here
  ASSERT_EQ(h.responses.size(), 1u);
  EXPECT_EQ(h.bank.holding_registers[1], 11);
  h.wait(h.timing.t35_us);
  EXPECT_EQ(h.responses.size(), 2u);
  EXPECT_EQ(h.bank.holding_registers[2], 22);
}

TEST(ModbusFraming, PowerUpWaitsForQuietLine) {
  SlaveHarness h;
  h.slave.begin(h.now_us);
  // Tail of a frame in progress at power-up: dropped (and it restarts the wait).
  h.feed(write_register(1, 11), 0);
  h.wait(h.timing.t35_us - 1);
  EXPECT_TRUE(h.responses.empty());
  EXPECT_EQ(h.slave.counters().bus_comm_errors, 0u) << "nothing seen as a frame";
  h.wait(1);  // t3.5 of silence: now idle
  EXPECT_EQ(h.transact(write_register(1, 11)).size(), 8u);
}

TEST(ModbusFraming, PowerUpAcceptsFrameAfterQuietLineWithoutProcess) {
  SlaveHarness h;
  h.slave.begin(h.now_us);
  h.feed(write_register(3, 33), h.timing.t35_us);
  h.wait(h.timing.t35_us);
  EXPECT_EQ(h.bank.holding_registers[3], 33);
}

TEST(ModbusFraming, WorksAcrossClockWrap) {
  SlaveHarness h(0xFFFFFFFFu - 3000u);  // the frame straddles 2^32 µs
  EXPECT_EQ(h.transact(write_register(4, 44)).size(), 8u);
  EXPECT_EQ(h.bank.holding_registers[4], 44);
}

TEST(ModbusFraming, StampsGoingBackwardsCountAsNoSilence) {
  SlaveHarness h;
  const Bytes adu = write_register(6, 66);
  h.feed(Bytes(adu.begin(), adu.begin() + 4), h.timing.t35_us);
  const uint32_t later = h.now_us;
  for (size_t i = 4; i < adu.size(); ++i) h.slave.on_byte(adu[i], later - 10u);
  h.now_us = later;
  h.wait(h.timing.t35_us);
  EXPECT_EQ(h.bank.holding_registers[6], 66);
}

TEST(ModbusFraming, RefusedResponseIsCountedAsNoResponse) {
  SlaveHarness h;
  h.sink_accepts = false;
  EXPECT_TRUE(h.transact(read_holding(0, 1)).empty());
  EXPECT_EQ(h.slave.stats().send_failures, 1u);
  EXPECT_EQ(h.slave.counters().no_responses, 1u);
}

}  // namespace
}  // namespace test
}  // namespace modbus
}  // namespace mb2co
