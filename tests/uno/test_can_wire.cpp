// The CAN wire behind the simulated Uno's MCP2515 (hil/uno/can_wire.h): each
// frame takes its exact length in bits at the rate the chip is set to, the
// lower identifier wins the idle wire, frames reach the chip at their last
// bit. The chip is driven by the real driver (shared/mcp2515) over the
// model's SPI, as the image drives it.
#include <gtest/gtest.h>

#include "can_wire.h"
#include "mcp2515.h"
#include "timing/can_bits.h"

namespace mb2co {
namespace uno {
namespace {

constexpr uint32_t kCpuHz = 16000000;
constexpr uint64_t kCyclesPerBitAt500k = kCpuHz / 500000;

CanFrame frame(uint32_t id, uint8_t dlc, uint8_t flags = 0) {
  CanFrame f{};
  f.id = id;
  f.dlc = dlc;
  f.flags = flags;
  for (uint8_t i = 0; i < dlc; ++i) f.data[i] = static_cast<uint8_t>(0xA0 + i);
  return f;
}

uint64_t cycles_500k(const CanFrame& f) {
  return timing::frame_bits_exact(f).total_bits * kCyclesPerBitAt500k;
}

class Wire : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(driver_.begin(mcp2515::Bitrate::k500k, mcp2515::Mode::kNormal)); }
  /// Runs the wire's events up to `until`.
  void run_to(uint64_t until) {
    while (wire_.next_event() <= until) wire_.advance(wire_.next_event());
  }

  CanWire wire_{kCpuHz};
  mcp2515::Driver driver_{wire_.chip().spi()};
};

TEST(Arbitration, LowerIdentifierWins) {
  EXPECT_TRUE(wins_arbitration(frame(0x181, 3), frame(0x701, 1)));
  EXPECT_FALSE(wins_arbitration(frame(0x701, 1), frame(0x181, 3)));
  EXPECT_TRUE(wins_arbitration(frame(0x123, 0), frame(0x123u << 18, 0, CanFrame::kExtended)))
      << "standard beats extended with the same base id";
  EXPECT_TRUE(wins_arbitration(frame(0x123, 0), frame(0x123, 0, CanFrame::kRtr))) << "data beats remote";
  EXPECT_TRUE(wins_arbitration(frame(0x100u << 18 | 5, 0, CanFrame::kExtended), frame(0x101, 0)))
      << "an extended frame with a lower base id wins";
}

TEST_F(Wire, SentFrameLeavesAfterItsBitsAtTheChipsRate) {
  EXPECT_EQ(wire_.chip().bitrate_bps(16000000), 500000u);
  const CanFrame f = frame(0x181, 3);
  ASSERT_TRUE(driver_.send(f));
  wire_.advance(1000);  // the end of the SPI instruction that set TXREQ
  EXPECT_EQ(wire_.next_event(), 1000 + cycles_500k(f));
  run_to(1000 + cycles_500k(f) - 1);
  EXPECT_TRUE(wire_.take_sent().empty()) << "not before its last bit";
  run_to(1000 + cycles_500k(f));
  const auto sent = wire_.take_sent();
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].frame.id, 0x181u);
  EXPECT_EQ(sent[0].end_cycle, 1000 + cycles_500k(f));
  EXPECT_EQ(wire_.next_event(), CanWire::kIdle);
}

TEST_F(Wire, ReceivedFrameReachesTheChipAtItsLastBit) {
  const CanFrame f = frame(0x601, 8);
  wire_.frame_from_bus(f, 500);
  EXPECT_FALSE(wire_.int_low());
  run_to(500 + cycles_500k(f));
  EXPECT_TRUE(wire_.int_low()) << "RX interrupt once the frame is in";
  CanFrame got{};
  driver_.service();
  ASSERT_TRUE(driver_.receive(got));
  EXPECT_EQ(got.id, 0x601u);
  EXPECT_EQ(got.data[7], 0xA7);
}

TEST_F(Wire, WaitingFramesGoByArbitrationBackToBack) {
  const CanFrame busy = frame(0x100, 8), high = frame(0x080, 0), low = frame(0x701, 1);
  wire_.frame_from_bus(busy, 0);  // holds the wire while the others queue up
  wire_.frame_from_bus(low, 10);
  ASSERT_TRUE(driver_.send(high));
  wire_.advance(20);
  run_to(UINT64_MAX - 1);
  const auto sent = wire_.take_sent();
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].end_cycle, cycles_500k(busy) + cycles_500k(high))
      << "080h won against 701h and followed the busy frame at once";
  CanFrame got{};
  driver_.service();
  ASSERT_TRUE(driver_.receive(got));
  EXPECT_EQ(got.id, 0x100u);
  ASSERT_TRUE(driver_.receive(got));
  EXPECT_EQ(got.id, 0x701u);
}

TEST_F(Wire, FramesHandedOverTogetherArriveAsTheyCame) {
  // mb2co-uno reads a socket's backlog in one go after the host held it up:
  // frames that came 2 ms apart must reach the chip 2 ms apart (an image
  // that reads each within a millisecond loses none), not back to back
  // (three of them would overrun the two receive buffers before it reads one).
  const CanFrame frames[] = {frame(0x702, 1), frame(0x703, 1), frame(0x601, 8)};
  const uint64_t came[] = {2000, 34000, 66000};
  for (int i = 0; i < 3; ++i) wire_.frame_from_bus(frames[i], 0, came[i]);
  EXPECT_EQ(wire_.next_event(), 2000u) << "idle until the first one came";
  for (int i = 0; i < 3; ++i) {
    const uint64_t in_at = came[i] + cycles_500k(frames[i]);
    run_to(in_at - 1);
    EXPECT_FALSE(wire_.int_low()) << "frame " << i << " not before its last bit";
    run_to(in_at);
    ASSERT_TRUE(wire_.int_low()) << "frame " << i;
    CanFrame got{};
    driver_.service();
    ASSERT_TRUE(driver_.receive(got));
    EXPECT_EQ(got.id, frames[i].id);
    EXPECT_FALSE(wire_.int_low());
  }
  EXPECT_EQ(wire_.rx_dropped(), 0u);
  EXPECT_EQ(wire_.next_event(), CanWire::kIdle);
}

TEST_F(Wire, ALateOrOutOfOrderArrivalIsNowAndInOrder) {
  const CanFrame a = frame(0x181, 2), b = frame(0x182, 2);
  wire_.frame_from_bus(a, 1000, 400);  // came before now: it is on the bus now
  EXPECT_EQ(wire_.next_event(), 1000 + cycles_500k(a));
  wire_.frame_from_bus(b, 1000, 900);  // never ahead of the one handed over before it
  run_to(1000 + cycles_500k(a));
  EXPECT_EQ(wire_.next_event(), 1000 + cycles_500k(a) + cycles_500k(b)) << "back to back, in order";
}

TEST_F(Wire, TheChipSendsWhileAFrameFromOutsideIsStillToCome) {
  const CanFrame in = frame(0x080, 0), out = frame(0x701, 1);
  wire_.frame_from_bus(in, 0, 100000);
  ASSERT_TRUE(driver_.send(out));
  wire_.advance(10);
  EXPECT_EQ(wire_.next_event(), 10 + cycles_500k(out)) << "080h would win, but it is not there yet";
  run_to(UINT64_MAX - 1);
  const auto sent = wire_.take_sent();
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].end_cycle, 10 + cycles_500k(out));
  EXPECT_TRUE(wire_.int_low()) << "and 080h arrived later";
}

TEST_F(Wire, AmongWaitingFramesFromOutsideTheLowestIdentifierGoesFirst) {
  // A backlog of low-priority traffic (a flood at the bus's capacity) and a
  // remote node's SDO response that came after it: the response takes the
  // wire when it is next free, as it wins arbitration on a real bus.
  const CanFrame flood = frame(0x790, 8), response = frame(0x582, 8);
  for (int i = 0; i < 5; ++i) wire_.frame_from_bus(flood, 0, 0);
  wire_.frame_from_bus(response, 0, 10);
  const uint64_t first_end = cycles_500k(flood);
  run_to(first_end);
  CanFrame got{};
  driver_.service();
  ASSERT_TRUE(driver_.receive(got));
  EXPECT_EQ(got.id, 0x790u) << "the frame on the wire when the response came";
  run_to(first_end + cycles_500k(response));
  driver_.service();
  ASSERT_TRUE(driver_.receive(got));
  EXPECT_EQ(got.id, 0x582u) << "next: before the four flood frames that waited longer";
  run_to(UINT64_MAX - 1);
  EXPECT_EQ(wire_.carried_in(), 6u);
  EXPECT_EQ(wire_.busy_cycles(), 5 * cycles_500k(flood) + cycles_500k(response));
}

}  // namespace
}  // namespace uno
}  // namespace mb2co
