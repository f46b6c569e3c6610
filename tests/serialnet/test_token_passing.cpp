// Multiple SYNC producers (seed 003 §3.2.7): 15 real I/O nodes pass the
// token (SYNC with the next node's id) when done or when their window ends;
// node 1 starts it and recovers it when it is lost, within
// SerialLink::token_recovery_bound_us().
#include <gtest/gtest.h>
#include <string.h>

#include <random>

#include "segment.h"

namespace mb2co {
namespace test {
namespace {

using serialnet::IdBits;

// The longest time from the end of one message to the end of the next, over
// messages that start at or after `from_us`, counting the messages the
// starter (talker 0) received intact or sent itself (intact or not: it
// cannot tell): the span T_recover bounds. Talker `ignore` (noise) does not
// count.
uint32_t longest_silence_us(const SerialBus& bus, uint32_t from_us, uint32_t* at_us = nullptr,
                            int ignore = -1) {
  uint32_t longest = 0;
  const SerialBus::Sent* prev = nullptr;
  for (const SerialBus::Sent& m : bus.log) {
    if ((m.collided && m.talker != 0) || m.talker == ignore) continue;
    if (prev != nullptr && static_cast<int32_t>(m.start_us - from_us) >= 0 &&
        m.end_us - prev->end_us > longest) {
      longest = m.end_us - prev->end_us;
      if (at_us != nullptr) *at_us = m.end_us;
    }
    prev = &m;
  }
  return longest;
}

TEST(TokenPassing, FifteenNodesBootBeatAndPassTheTokenEarlyWhenIdle) {
  Segment seg(IdBits::k7, 15, true);
  seg.bring_up(200, false, 1000000);
  for (uint8_t id = 1; id <= 15; ++id) {
    EXPECT_EQ(seg.node(id).node().nmt_state(), canopen::kNmtOperational) << int(id);
    ASSERT_EQ(seg.sent_by(id, static_cast<uint16_t>(0x700u + id)).front().msg.data[0],
              canopen::kNmtInitialising);
    const auto hb = seg.sent_by(id, static_cast<uint16_t>(0x700u + id));
    EXPECT_GE(hb.size(), 5u) << int(id);
    EXPECT_LE(hb.size(), 7u) << int(id);
  }
  // An idle holder passes at once: far more rounds than polling's fixed
  // windows would give (1 s / cycle_bound).
  const uint32_t polled_rounds = 1000000u / seg.cycle_bound_us();
  for (uint8_t id = 1; id <= 15; ++id)
    EXPECT_GT(seg.node(id).link.counters().windows, 4 * polled_rounds) << int(id);
  EXPECT_GT(seg.check_windows(), 15 * 6);
  EXPECT_EQ(seg.bus.collisions, 0);
  EXPECT_EQ(seg.node(1).link.counters().token_recoveries, 0);
  EXPECT_LE(longest_silence_us(seg.bus, 0), seg.config.window_us);
}

TEST(TokenPassing, PdosAndSdoUploadsRideTheToken) {
  Segment seg(IdBits::k7, 15, true);
  seg.bring_up(0, true, 100000);
  std::mt19937 rng(9);
  // A token round takes at most N windows: the PDO leaves in the next one.
  const uint32_t bound_us = seg.count() * seg.config.window_us + seg.config.window_us;
  for (int round = 0; round < 20; ++round) {
    seg.bus.run_for(static_cast<uint32_t>(rng() % 30000u));
    const uint8_t src = static_cast<uint8_t>(1u + rng() % 14u);
    const uint8_t value = static_cast<uint8_t>(0x40 + round);
    const uint32_t t0 = seg.bus.now;
    seg.node(src).io.set_input(1, value);
    seg.bus.run_for(bound_us);
    EXPECT_EQ(seg.node(static_cast<uint8_t>(src + 1)).io.output(1), value) << "round " << round;
    const auto pdos = seg.sent_by(src, static_cast<uint16_t>(0x180u + src));
    ASSERT_FALSE(pdos.empty());
    EXPECT_EQ(pdos.back().msg.data[1], value);
    EXPECT_LE(pdos.back().end_us - t0, bound_us);
  }
  uint8_t name[32] = {};
  ASSERT_EQ(seg.upload(9, 0x1008, 0, name, sizeof name), 14);
  EXPECT_EQ(std::string(reinterpret_cast<char*>(name), 14), "mb2co I/O node");
  uint8_t vendor[4] = {};
  EXPECT_EQ(seg.upload(15, 0x1018, 1, vendor, sizeof vendor), 4);
  EXPECT_GT(seg.check_windows(), 40);
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(TokenPassing, ANodeRemovedWhileHoldingTheTokenIsSkippedWithinTheBound) {
  Segment seg(IdBits::k7, 15, true);
  seg.bring_up(100, false, 300000);
  // Unplug node 6 in the middle of its window: the token dies with it.
  ASSERT_TRUE(seg.run_until_token_at(6));
  const uint32_t t_remove = seg.bus.now;
  const uint16_t windows7 = seg.node(7).link.counters().windows;
  seg.bus.detach(5);
  seg.bus.run_for(1000000);

  const uint32_t bound = seg.node(1).link.token_recovery_bound_us();
  EXPECT_EQ(bound, seg.config.window_us + seg.config.guard_us +
                       seg.node(1).link.line_time_us(seg.node(1).link.sync_frame_bytes()));
  uint32_t at = 0;
  const uint32_t longest = longest_silence_us(seg.bus, t_remove, &at);
  EXPECT_GT(longest, seg.config.window_us) << "a recovery happened";
  EXPECT_LE(longest, bound) << "at " << at;
  // Once per round (the ring still names node 6), never more.
  const uint16_t recoveries = seg.node(1).link.counters().token_recoveries;
  EXPECT_GE(recoveries, 1000000u / (seg.count() * seg.config.window_us + bound));
  EXPECT_EQ(recoveries, seg.node(7).link.counters().windows - windows7);
  // The others go on: node 7 (after the gap) and everyone's heartbeats.
  EXPECT_GT(seg.node(7).link.counters().windows - windows7, 10);
  for (uint8_t id = 1; id <= 15; ++id) {
    if (id == 6) continue;
    const auto hb = seg.sent_by(id, static_cast<uint16_t>(0x700u + id));
    EXPECT_GE(hb.size(), 12u) << int(id);
  }
  seg.check_windows(t_remove);
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(TokenPassing, ALostPassIsRecoveredAndTheRingGoesOn) {
  Segment seg(IdBits::k7, 8, true);
  seg.bring_up(100, false, 200000);
  // Noise over node 3's pass: wait until node 3 holds the token and sent
  // its SYNC, then jam it.
  ASSERT_TRUE(seg.run_until_token_at(3));
  for (int i = 0; i < 1000 && seg.node(3).link.holds_token(); ++i) seg.bus.run_for(10);
  const uint32_t t_jam = seg.bus.now;
  seg.bus.inject(7, {0x55, 0x55, 0x55});
  seg.bus.run_for(500000);
  EXPECT_EQ(seg.bus.collisions, 1);
  EXPECT_GE(seg.node(1).link.counters().token_recoveries, 1);
  EXPECT_LE(longest_silence_us(seg.bus, t_jam), seg.node(1).link.token_recovery_bound_us());
  for (uint8_t id = 1; id <= 8; ++id) {
    const auto hb = seg.sent_by(id, static_cast<uint16_t>(0x700u + id));
    ASSERT_FALSE(hb.empty());
    EXPECT_GT(hb.back().end_us - t_jam, 300000u) << "node " << int(id) << " still beats";
  }
}

TEST(TokenPassing, NoiseBurstsNeverStallTheRingLongerThanTheBound) {
  Segment seg(IdBits::k7, 15, true);
  seg.bring_up(100, true, 200000);
  const int noise = 15;  // a talker that is no device: noise on the line
  std::mt19937 rng(21);
  const uint32_t t0 = seg.bus.now;
  uint8_t value = 0;
  for (int burst = 0; burst < 100; ++burst) {
    seg.bus.run_for(50000u + static_cast<uint32_t>(rng() % 50000u));
    std::vector<uint8_t> garbage(1u + rng() % 20u);
    for (uint8_t& b : garbage) b = static_cast<uint8_t>(rng());
    seg.bus.inject(noise, garbage);
    seg.node(1).io.set_input(0, ++value);  // process data keeps flowing
  }
  seg.bus.run_for(200000);
  EXPECT_GT(seg.bus.collisions, 10) << "the noise hit messages";
  EXPECT_GT(seg.node(1).link.counters().token_recoveries, 0);
  EXPECT_LE(longest_silence_us(seg.bus, t0, nullptr, noise), seg.node(1).link.token_recovery_bound_us());
  EXPECT_EQ(seg.node(2).io.output(0), value);
  for (uint8_t id = 1; id <= 15; ++id) {
    EXPECT_EQ(seg.node(id).node().nmt_state(), canopen::kNmtOperational) << int(id);
    // ~7.7 s of 100 ms heartbeats: most of them arrive.
    EXPECT_GE(seg.sent_by(id, static_cast<uint16_t>(0x700u + id)).size(), 60u) << int(id);
  }
}

TEST(TokenPassing, TheBoundUsesTheLongestWindow) {
  static const uint32_t windows[8] = {4000, 4000, 4000, 9000, 4000, 4000, 4000, 4000};
  Segment seg(IdBits::k7, 8, true, 4000, windows);
  seg.bring_up(100, false, 200000);
  EXPECT_EQ(seg.node(1).link.token_recovery_bound_us(),
            9000u + seg.config.guard_us + seg.node(1).link.line_time_us(seg.node(1).link.sync_frame_bytes()));
  ASSERT_TRUE(seg.run_until_token_at(6));
  const uint32_t t_remove = seg.bus.now;
  seg.bus.detach(5);
  seg.bus.run_for(500000);
  const uint32_t longest = longest_silence_us(seg.bus, t_remove);
  EXPECT_GT(longest, 9000u) << "the starter waits W_max + G";
  EXPECT_LE(longest, seg.node(1).link.token_recovery_bound_us());
  EXPECT_GT(seg.node(1).link.counters().token_recoveries, 10);
  seg.check_windows(t_remove);
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(TokenPassing, WorksInEveryConnectionSet) {
  check_every_connection_set(true);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
