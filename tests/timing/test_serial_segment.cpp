// Timing of a serial CANopen segment (shared/timing/serial_segment.h)
// against figures computed by hand, and against the data link's own
// numbers where both state the same quantity.
#include <gtest/gtest.h>

#include "timing/serial_segment.h"

namespace mb2co {
namespace timing {
namespace {

using serialnet::Access;
using serialnet::BusConfig;
using serialnet::IdBits;

BusConfig segment(IdBits bits, uint8_t nodes, Access access, uint32_t window_us = 3600,
                  uint32_t guard_us = 100, uint32_t baud = 115200) {
  BusConfig c = {};
  c.set = serialnet::connection_set(bits);
  c.baud = baud;
  c.access = access;
  c.first_node = 1;
  c.last_node = nodes;
  c.window_us = window_us;
  c.guard_us = guard_us;
  return c;
}

TEST(SerialSegment, MessageBytesAndTimesNominalAndWorstCase) {
  // 115200 baud: 10 bits = 86.8 µs, the link's byte time rounds it up to 87.
  const SerialMessageTime pdo = serial_message_time(serialnet::connection_set(IdBits::k7), 115200, 8);
  EXPECT_EQ(pdo.bytes, 13);        // flag, id, length, 8 data, CRC 2
  EXPECT_EQ(pdo.bytes_worst, 25);  // flag + 12 content bytes, each stuffed
  EXPECT_EQ(pdo.us, 13u * 87u);
  EXPECT_EQ(pdo.worst_us, 2175u);
  // The 11-bit set has 2 id bytes: the longest message of all, 27 bytes.
  const SerialMessageTime can11 = serial_message_time(serialnet::connection_set(IdBits::k11), 115200, 8);
  EXPECT_EQ(can11.bytes, 14);
  EXPECT_EQ(can11.bytes_worst, 27);
  EXPECT_EQ(can11.bytes_worst, serialnet::kMaxEncodedBytes);
  EXPECT_EQ(can11.worst_us, 2349u);
  // No data bytes (the codec's shortest message), 6-bit set at 19200 baud:
  // 5 bytes, 9 stuffed.
  const SerialMessageTime empty = serial_message_time(serialnet::connection_set(IdBits::k6), 19200, 0);
  EXPECT_EQ(empty.bytes, 5);
  EXPECT_EQ(empty.bytes_worst, 9);
  EXPECT_EQ(empty.us, 5u * 521u);  // 10/19200 s = 520.8 µs → 521
  // More than 8 data bytes count as 8: the codec carries no more.
  EXPECT_EQ(serial_message_time(serialnet::connection_set(IdBits::k8), 115200, 12).bytes, 13);
}

TEST(SerialSegment, SyncCycleRoundAndRecoveryOfFifteenNodes) {
  const BusConfig polled = segment(IdBits::k7, 15, Access::kPoller);
  // T_sync: flag + (id, length, counter, CRC 2) stuffed = 11 bytes = 957 µs.
  EXPECT_EQ(serial_sync_us(polled), 957u);
  EXPECT_EQ(poll_cycle_us(polled), 15u * (3600u + 957u));  // 68,355 µs
  EXPECT_EQ(access_cycle_us(polled, 3), 68355u) << "polling has no recovery";

  const BusConfig token = segment(IdBits::k7, 15, Access::kTokenStarter);
  EXPECT_EQ(token_round_us(token, 0), 54000u);
  EXPECT_EQ(token_recovery_us(token), 3600u + 100u + 957u);
  EXPECT_EQ(token_round_us(token, 1), 54000u + 4657u);
  EXPECT_EQ(token_round_us(token, 2), 54000u + 2u * 4657u);
  EXPECT_EQ(token_round_idle_us(token), 15u * 957u);
  EXPECT_EQ(access_cycle_us(token, 1), 58657u);
}

TEST(SerialSegment, TheSameNumbersTheLinkSchedulesWith) {
  const BusConfig token = segment(IdBits::k8, 31, Access::kTokenStarter, 5000, 150, 57600);
  const modbus::ByteSink nowhere = {[](void*, const uint8_t*, uint16_t) { return true; }, nullptr};
  const serialnet::SerialLink link(token, 1, nowhere);
  EXPECT_EQ(token_recovery_us(token), link.token_recovery_bound_us());
  EXPECT_EQ(serial_sync_us(token), link.line_time_us(link.sync_frame_bytes()));
}

TEST(SerialSegment, PerNodeWindows) {
  static const uint32_t windows[4] = {4000, 4000, 9000, 4000};
  BusConfig c = segment(IdBits::k7, 4, Access::kPoller, 4000);
  c.node_windows_us = windows;
  EXPECT_EQ(poll_cycle_us(c), 21000u + 4u * 957u);  // 24,828 µs
  c.access = Access::kToken;
  EXPECT_EQ(token_round_us(c, 0), 21000u);
  EXPECT_EQ(token_recovery_us(c), 9000u + 100u + 957u) << "W_max, not the node's W";
  // Node 3's long window holds what node 1's does not.
  const uint8_t ahead[2] = {8, 8};
  EXPECT_FALSE(serial_latency(c, 1, 8, ahead, 2, 0).fits);
  EXPECT_TRUE(serial_latency(c, 3, 8, ahead, 2, 0).fits);
}

TEST(SerialSegment, LatencyUnderPolling) {
  const BusConfig c = segment(IdBits::k7, 15, Access::kPolled);
  // A 2-byte TPDO: 13 bytes stuffed = 1131 µs, after at most one cycle.
  SerialLatency l = serial_latency(c, 7, 2, nullptr, 0, 0);
  EXPECT_TRUE(l.fits);
  EXPECT_EQ(l.wait_us, 68355u);
  EXPECT_EQ(l.own_us, 1131u);
  EXPECT_EQ(l.budget_us, 3500u);  // W - G
  EXPECT_EQ(l.worst_us, 69486u);
  EXPECT_LE(l.worst_us, poll_cycle_us(c) + c.window_us) << "never above the author's cycle + W";
  // An EMCY (8 bytes) queued ahead: 2175 + 1131 = 3306 µs still fit 3500.
  const uint8_t emcy[1] = {8};
  l = serial_latency(c, 7, 2, emcy, 1, 0);
  EXPECT_TRUE(l.fits);
  EXPECT_EQ(l.ahead_us, 2175u);
  EXPECT_EQ(l.worst_us, 68355u + 2175u + 1131u);
  // Two of them do not: the bound is refused, not made up.
  const uint8_t two[2] = {8, 8};
  l = serial_latency(c, 7, 2, two, 2, 0);
  EXPECT_FALSE(l.fits);
  EXPECT_EQ(l.worst_us, 0u);
}

TEST(SerialSegment, LatencyUnderTokenPassing) {
  const BusConfig c = segment(IdBits::k7, 15, Access::kToken);
  // The holder keeps T_sync for its pass: budget 3600 - 100 - 957 = 2543 µs.
  SerialLatency l = serial_latency(c, 4, 2, nullptr, 0, 0);
  EXPECT_TRUE(l.fits);
  EXPECT_EQ(l.budget_us, 2543u);
  EXPECT_EQ(l.worst_us, 54000u + 1131u);
  // A missing node lengthens the round by T_recover.
  EXPECT_EQ(serial_latency(c, 4, 2, nullptr, 0, 1).worst_us, 58657u + 1131u);
  const uint8_t emcy[1] = {8};
  EXPECT_FALSE(serial_latency(c, 4, 2, emcy, 1, 0).fits) << "3306 µs > 2543 µs";
}

TEST(SerialSegment, WhatABridgeAdds) {
  const BusConfig c = segment(IdBits::k7, 15, Access::kPolled);
  const SerialLatency up = serial_latency(c, 3, 2, nullptr, 0, 0);
  // To CAN: 200 µs forwarding, then an 8-byte frame at 500 kbit/s with
  // worst-case stuffing: 55 + 80 = 135 bits = 270 µs.
  EXPECT_EQ(serial_to_can_us(up, 200, 500000, 8), 69486u + 200u + 270u);
  // From CAN: the bridge (node 15) forwards 200 µs later, then waits for its
  // window like any node: a cycle plus the 8-byte frame (2175 µs).
  const SerialLatency down = can_to_serial(c, 15, 8, nullptr, 0, 200);
  EXPECT_TRUE(down.fits);
  EXPECT_EQ(down.worst_us, 200u + 68355u + 2175u);
}

}  // namespace
}  // namespace timing
}  // namespace mb2co
