// The CAN bus model: arbitration, exact frame lengths and times, the
// MCP2515's three transmit buffers, error frames, bus-off and recovery.
#include <gtest/gtest.h>

#include <vector>

#include "sim/can_bus.h"
#include "timing/can_bits.h"

namespace mb2co {
namespace sim {
namespace {

CanFrame frame(uint32_t id, uint8_t dlc, uint8_t fill = 0x55) {
  CanFrame f = {};
  f.id = id;
  f.dlc = dlc;
  for (uint8_t i = 0; i < 8; ++i) f.data[i] = static_cast<uint8_t>(fill + i);
  return f;
}

struct Bench {
  explicit Bench(uint32_t bitrate = 500000, int nodes = 3, uint64_t seed = 1) : bus(q, bitrate, seed) {
    for (int i = 0; i < nodes; ++i) c.emplace_back(new CanController(bus));
    bus.observer = [this](const CanAttempt& a) { log.push_back(a); };
  }
  EventQueue q;
  CanBus bus;
  std::vector<std::unique_ptr<CanController>> c;
  std::vector<CanAttempt> log;
};

TEST(CanBus, LowestIdentifierWinsArbitrationWhenQueuedTogether) {
  Bench b;
  ASSERT_TRUE(b.c[0]->send(frame(0x300, 2)));
  ASSERT_TRUE(b.c[1]->send(frame(0x180, 2)));
  ASSERT_TRUE(b.c[2]->send(frame(0x200, 2)));
  b.q.run_until(kNsPerS);
  ASSERT_EQ(b.log.size(), 3u);
  EXPECT_EQ(b.log[0].frame.id, 0x180u);
  EXPECT_EQ(b.log[1].frame.id, 0x200u);
  EXPECT_EQ(b.log[2].frame.id, 0x300u);
  // Back to back: each starts when the previous one's IFS ends.
  EXPECT_EQ(b.log[1].sof_ns, b.log[0].free_ns);
  EXPECT_EQ(b.log[2].sof_ns, b.log[1].free_ns);
}

TEST(CanBus, AFrameStartedIsNotPreemptedAndLateQueuersJoinOnlyDuringSof) {
  Bench b;
  ASSERT_TRUE(b.c[0]->send(frame(0x400, 8)));
  // Queued within the SOF bit: joins the arbitration and wins.
  b.q.run_until(b.bus.bit_ns() / 2);
  ASSERT_TRUE(b.c[1]->send(frame(0x100, 1)));
  // Queued after SOF: waits for the frame in progress although it wins later.
  b.q.run_until(3 * b.bus.bit_ns());
  ASSERT_TRUE(b.c[2]->send(frame(0x080, 0)));
  b.q.run_until(kNsPerS);
  ASSERT_EQ(b.log.size(), 3u);
  EXPECT_EQ(b.log[0].frame.id, 0x100u);
  EXPECT_EQ(b.log[0].sof_ns, 0u);
  EXPECT_EQ(b.log[1].frame.id, 0x080u);
  EXPECT_EQ(b.log[2].frame.id, 0x400u);
}

TEST(CanBus, EveryFrameLastsItsExactStuffedLength) {
  for (uint32_t bitrate : {125000u, 250000u, 500000u, 1000000u}) {
    Bench b(bitrate, 2);
    Rng rng(bitrate);
    std::vector<CanFrame> sent;
    for (int i = 0; i < 300; ++i) {
      CanFrame f = frame(static_cast<uint32_t>(rng.below(0x800)), static_cast<uint8_t>(rng.below(9)));
      for (uint8_t& d : f.data) d = static_cast<uint8_t>(rng.below(4) == 0 ? 0x00 : rng.below(256));
      if (rng.below(10) == 0) {
        f.flags = CanFrame::kExtended;
        f.id = static_cast<uint32_t>(rng.below(0x20000000));
      }
      sent.push_back(f);
      ASSERT_TRUE(b.c[0]->send(f));
      b.q.run_until(b.q.now() + kNsPerS / 10);
      ASSERT_EQ(b.log.size(), sent.size());
      const CanAttempt& a = b.log.back();
      const timing::ExactFrameBits want = timing::frame_bits_exact(f);
      EXPECT_EQ(a.bits, want.total_bits);
      EXPECT_EQ(a.stuff_bits, want.stuff_bits);
      EXPECT_EQ(a.end_ns - a.sof_ns, SimNs{want.total_bits - 3u} * b.bus.bit_ns());
      EXPECT_EQ(a.free_ns - a.sof_ns, SimNs{want.total_bits} * b.bus.bit_ns());
      CanFrame got;
      ASSERT_TRUE(b.c[1]->receive(got));
      EXPECT_EQ(got.id, f.id);
    }
  }
}

TEST(CanBus, ThreeTransmitBuffersSendLowestIdFirstAndFifoAmongEqualIds) {
  Bench b(500000, 2);
  // The bus is busy with another node's long frame while this one queues.
  ASSERT_TRUE(b.c[1]->send(frame(0x010, 8)));
  b.q.run_until(5 * b.bus.bit_ns());
  ASSERT_TRUE(b.c[0]->send(frame(0x300, 1, 1)));
  ASSERT_TRUE(b.c[0]->send(frame(0x200, 1, 2)));
  ASSERT_TRUE(b.c[0]->send(frame(0x200, 1, 3)));
  EXPECT_EQ(b.c[0]->free_tx(), 0);
  EXPECT_FALSE(b.c[0]->send(frame(0x100, 1)));  // all three busy: refused
  EXPECT_EQ(b.c[0]->counters().tx_refused, 1u);
  b.q.run_until(kNsPerS);
  ASSERT_EQ(b.log.size(), 4u);
  EXPECT_EQ(b.log[1].frame.id, 0x200u);
  EXPECT_EQ(b.log[1].frame.data[0], 2);
  EXPECT_EQ(b.log[2].frame.id, 0x200u);
  EXPECT_EQ(b.log[2].frame.data[0], 3);
  EXPECT_EQ(b.log[3].frame.id, 0x300u);
  EXPECT_EQ(b.c[0]->free_tx(), 3);
}

TEST(CanBus, TwoReceiveBuffersOverflowWhenNotRead) {
  Bench b(1000000, 2);
  for (uint32_t id : {0x181u, 0x182u, 0x183u}) ASSERT_TRUE(b.c[0]->send(frame(id, 1)));
  b.q.run_until(kNsPerS);
  EXPECT_EQ(b.c[1]->rx_waiting(), 2u);
  EXPECT_EQ(b.c[1]->counters().rx_overflows, 1u);
  CanFrame f;
  ASSERT_TRUE(b.c[1]->receive(f));
  EXPECT_EQ(f.id, 0x181u);
}

TEST(CanBus, CorruptedFramesAreRetransmittedAfterAnErrorFrame) {
  Bench b(500000, 2);
  b.bus.set_corruption_ppm(500000);  // every other attempt on average
  for (int i = 0; i < 40; ++i) {
    ASSERT_TRUE(b.c[0]->send(frame(0x181, 2, static_cast<uint8_t>(i))));
    b.q.run_until(b.q.now() + 50 * kNsPerMs);
    CanFrame f;
    ASSERT_TRUE(b.c[1]->receive(f));
    EXPECT_EQ(f.data[0], static_cast<uint8_t>(i));
  }
  EXPECT_GT(b.bus.error_frames(), 5u);
  EXPECT_EQ(b.bus.ack_error_frames(), 0u) << "a corrupted frame is no ACK error: the receiver was there";
  EXPECT_EQ(b.c[0]->counters().tx_ok, 40u);
  for (const CanAttempt& a : b.log) {
    if (a.error) {
      EXPECT_EQ(a.free_ns - a.end_ns, 23u * b.bus.bit_ns());
    }
  }
}

TEST(CanBus, ABrokenTransmitterGoesBusOffAndRecoversWhenRepaired) {
  Bench b(500000, 2);
  std::vector<bool> off_events;
  b.bus.on_bus_off = [&](int, bool off) { off_events.push_back(off); };
  b.c[0]->set_tx_broken(true);
  ASSERT_TRUE(b.c[0]->send(frame(0x701, 1)));
  b.q.run_until(3 * kNsPerMs);  // 32 attempts of 36 bits; recovery needs 1408 bits more
  EXPECT_EQ(b.c[0]->state(), CanErrorState::kBusOff);
  EXPECT_EQ(b.c[0]->counters().tx_errors, 32u);  // 32 x 8 = 256: bus-off
  EXPECT_EQ(b.c[0]->counters().bus_offs, 1u);
  b.c[0]->set_tx_broken(false);
  b.q.run_until(kNsPerS);
  EXPECT_EQ(b.c[0]->state(), CanErrorState::kActive);
  EXPECT_EQ(b.c[0]->counters().tx_ok, 1u);
  ASSERT_GE(off_events.size(), 2u);
  EXPECT_TRUE(off_events[0]);
  EXPECT_FALSE(off_events[1]);
}

TEST(CanBus, ALoneNodeGetsNoAcknowledgeAndStaysErrorPassive) {
  Bench b(500000, 2);
  b.c[1]->set_powered(false);
  ASSERT_TRUE(b.c[0]->send(frame(0x701, 1)));
  b.q.run_until(100 * kNsPerMs);
  EXPECT_EQ(b.c[0]->state(), CanErrorState::kPassive);  // ACK errors never make it bus-off
  EXPECT_GT(b.bus.error_frames(), 100u);
  EXPECT_EQ(b.bus.ack_error_frames(), b.bus.error_frames()) << "every one unacknowledged";
  b.c[1]->set_powered(true);
  b.q.run_until(200 * kNsPerMs);
  EXPECT_EQ(b.c[0]->counters().tx_ok, 1u);
  EXPECT_EQ(b.bus.ack_error_frames(), b.bus.error_frames()) << "acknowledged once the other one is up";
}

}  // namespace
}  // namespace sim
}  // namespace mb2co
