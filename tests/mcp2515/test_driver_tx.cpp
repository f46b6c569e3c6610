// send(): three buffers, arbitration order on the bus, encoding of ids, RTR
// and extended frames, refusals, the CanSink adapter.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>
#include <vector>

#include "mcp2515_regs.h"
#include "test_helpers.h"

namespace mb2co::mcp2515::test {
namespace {

using TxTest = DriverTest;

std::vector<uint32_t> ids_on(const std::vector<CanFrame>& bus) {
  std::vector<uint32_t> ids;
  for (const auto& f : bus) ids.push_back(f.id);
  return ids;
}

TEST_F(TxTest, FrameGoesOutUnchanged) {
  const CanFrame f = frame(0x7FF, {1, 2, 3, 4, 5, 6, 7, 8});
  ASSERT_TRUE(driver.send(f));
  EXPECT_EQ(chip.transmit(), 1);
  ASSERT_EQ(chip.bus.size(), 1u);
  EXPECT_EQ(chip.bus[0], f);
  EXPECT_EQ(driver.counters().tx_frames, 1);
}

TEST_F(TxTest, ThreeBuffersThenRefusedAndCounted) {
  EXPECT_TRUE(driver.send(frame(0x301)));
  EXPECT_TRUE(driver.send(frame(0x302)));
  EXPECT_TRUE(driver.send(frame(0x303)));
  EXPECT_FALSE(driver.send(frame(0x304)));
  EXPECT_EQ(driver.counters().tx_full, 1);
  EXPECT_EQ(chip.transmit(1), 1);
  EXPECT_TRUE(driver.send(frame(0x305)));
  EXPECT_EQ(chip.transmit(), 3);
  EXPECT_EQ(ids_on(chip.bus), (std::vector<uint32_t>{0x301, 0x302, 0x303, 0x305}));
}

TEST_F(TxTest, PendingFramesLeaveInIdOrderNotQueueOrder) {
  ASSERT_TRUE(driver.send(frame(0x300)));
  ASSERT_TRUE(driver.send(frame(0x100)));
  ASSERT_TRUE(driver.send(frame(0x200)));
  EXPECT_EQ(chip.transmit(1), 1);
  ASSERT_TRUE(driver.send(frame(0x050)));  // overtakes both still pending
  EXPECT_EQ(chip.transmit(), 3);
  EXPECT_EQ(ids_on(chip.bus), (std::vector<uint32_t>{0x100, 0x050, 0x200, 0x300}));
}

TEST_F(TxTest, EqualIdsStayFirstInFirstOut) {
  for (uint8_t i = 1; i <= 3; ++i) ASSERT_TRUE(driver.send(frame(0x581, {i})));
  EXPECT_EQ(chip.transmit(1), 1);
  ASSERT_TRUE(driver.send(frame(0x581, {4})));
  EXPECT_EQ(chip.transmit(), 3);
  ASSERT_EQ(chip.bus.size(), 4u);
  for (uint8_t i = 0; i < 4; ++i) EXPECT_EQ(chip.bus[i].data[0], i + 1);
}

TEST_F(TxTest, StandardBeatsExtendedWithTheSameBaseIdAndDataBeatsRemote) {
  const CanFrame ext = frame((0x123u << 18) | 1u, {1}, CanFrame::kExtended);
  const CanFrame rtr = remote(0x123, 1);
  const CanFrame data = frame(0x123, {2});
  ASSERT_TRUE(driver.send(ext));
  ASSERT_TRUE(driver.send(rtr));
  ASSERT_TRUE(driver.send(data));
  chip.transmit();
  ASSERT_EQ(chip.bus.size(), 3u);
  EXPECT_EQ(chip.bus[0], data);
  EXPECT_EQ(chip.bus[1], rtr);
  EXPECT_EQ(chip.bus[2], ext);
}

// Any interleaving of sends and bus progress: each frame the chip sends is the
// one bus arbitration among the pending frames would pick (lowest key, then
// oldest).
TEST_F(TxTest, RandomTrafficAlwaysSendsTheArbitrationWinner) {
  std::mt19937 engine(7);
  auto rng = [&engine] { return static_cast<uint32_t>(engine()); };
  std::vector<std::tuple<uint32_t, int, CanFrame>> pending;  // key, sequence, frame
  int sequence = 0;
  for (int step = 0; step < 3000; ++step) {
    if (rng() % 3 != 0) {
      const bool ext = rng() % 4 == 0;
      CanFrame f = frame(ext ? rng() % 0x20000000u : rng() % 8u * 0x100u + rng() % 4u,
                         {static_cast<uint8_t>(sequence)}, ext ? CanFrame::kExtended : 0);
      if (rng() % 8 == 0) f = remote(f.id, 2, f.flags);
      const bool full = pending.size() == 3;
      ASSERT_EQ(driver.send(f), !full);
      if (!full) pending.emplace_back(arbitration_key(f), sequence++, f);
    } else if (!pending.empty()) {
      ASSERT_EQ(chip.transmit(1), 1);
      const auto winner = std::min_element(pending.begin(), pending.end(), [](const auto& a, const auto& b) {
        return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
      });
      ASSERT_EQ(chip.bus.back(), std::get<2>(*winner)) << "step " << step;
      pending.erase(winner);
    }
  }
}

TEST_F(TxTest, RemoteAndExtendedFramesAreEncoded) {
  const CanFrame frames[] = {remote(0x701, 0), remote(0x601, 8),
                             frame(0x1FFFFFFF, {9, 8}, CanFrame::kExtended),
                             frame(0, {}, CanFrame::kExtended), remote(0x18FF1234, 3, CanFrame::kExtended)};
  for (const CanFrame& f : frames) {
    ASSERT_TRUE(driver.send(f));
    ASSERT_EQ(chip.transmit(), 1);
    EXPECT_EQ(chip.bus.back(), f);
  }
}

TEST_F(TxTest, InvalidFramesAreRefusedAndCounted) {
  CanFrame long_frame = frame(0x100);
  long_frame.dlc = 9;
  EXPECT_FALSE(driver.send(long_frame));
  EXPECT_FALSE(driver.send(frame(0x800)));
  EXPECT_FALSE(driver.send(frame(0x20000000, {}, CanFrame::kExtended)));
  EXPECT_EQ(driver.counters().tx_invalid, 3);
  EXPECT_EQ(chip.transmit(), 0);
  EXPECT_EQ(driver.counters().tx_frames, 0);
}

TEST_F(TxTest, CanSinkSendsThroughTheDriver) {
  const CanSink sink = driver.sink();
  EXPECT_TRUE(sink.send(sink.ctx, frame(0x181, {0x11})));
  chip.transmit();
  ASSERT_EQ(chip.bus.size(), 1u);
  EXPECT_EQ(chip.bus[0], frame(0x181, {0x11}));
}

TEST_F(TxTest, NothingGoesOutInListenOnlyMode) {
  ASSERT_TRUE(driver.set_mode(Mode::kListenOnly));
  ASSERT_TRUE(driver.send(frame(0x100)));
  EXPECT_EQ(chip.transmit(), 0);
  ASSERT_TRUE(driver.set_mode(Mode::kNormal));
  EXPECT_EQ(chip.transmit(), 1);
}

}  // namespace
}  // namespace mb2co::mcp2515::test
