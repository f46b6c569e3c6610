// One SYNC producer polls 15 real I/O nodes on a 7-bit segment (seed 003
// §3.2.6): boot-ups, heartbeats, NMT, PDOs from node to node and SDO
// uploads, every message inside its sender's window.
#include <gtest/gtest.h>
#include <string.h>

#include <random>

#include "segment.h"

namespace mb2co {
namespace test {
namespace {

using serialnet::IdBits;

TEST(Polling, BootUpsHeartbeatsAndNmtOfFifteenNodesEachInItsWindow) {
  Segment seg(IdBits::k7, 15, false);
  seg.start(200);
  seg.bus.run_for(100000);
  // Every boot-up once, from its node, and heard by the others.
  for (uint8_t id = 1; id <= 15; ++id) {
    const auto boot = seg.sent_by(id, static_cast<uint16_t>(0x700u + id));
    ASSERT_EQ(boot.size(), 1u) << "node " << int(id);
    EXPECT_EQ(boot[0].msg.length, 1);
    EXPECT_EQ(boot[0].msg.data[0], canopen::kNmtInitialising);
  }
  int boot_ups_heard = 0;
  for (const auto& r : seg.node(1).received) {
    if (r.second.id > 0x700u && r.second.dlc == 1 && r.second.data[0] == 0) ++boot_ups_heard;
  }
  EXPECT_EQ(boot_ups_heard, 14);

  seg.nmt_start_all();
  seg.bus.run_for(1000000);
  for (uint8_t id = 1; id <= 15; ++id) {
    EXPECT_EQ(seg.node(id).node().nmt_state(), canopen::kNmtOperational) << int(id);
    // 200 ms heartbeats over ~1 s: 4..6 of them, state operational at the end.
    const auto hb = seg.sent_by(id, static_cast<uint16_t>(0x700u + id));
    EXPECT_GE(hb.size(), 5u) << int(id);
    EXPECT_LE(hb.size(), 7u) << int(id);
    EXPECT_EQ(hb.back().msg.data[0], canopen::kNmtOperational);
    EXPECT_GT(seg.node(id).link.counters().windows, 15u);
  }
  EXPECT_GT(seg.check_windows(), 15 * 6);
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(Polling, PdosTravelNodeToNodeWithinTheCycleBound) {
  Segment seg(IdBits::k7, 15, false);
  seg.bring_up(500, true, 200000);
  std::mt19937 rng(5);  // NOLINT: result_type is 32 bits wide
  const uint32_t bound_us = seg.cycle_bound_us() + seg.config.window_us;
  for (int round = 0; round < 20; ++round) {
    // An input changes at a random moment on a random node; the next node's
    // output follows, carried by a TPDO sent in the source's window.
    seg.bus.run_for(static_cast<uint32_t>(rng() % 50000u));
    const uint8_t src = static_cast<uint8_t>(1u + rng() % 14u);
    const uint8_t value = static_cast<uint8_t>(round + 1);
    const uint32_t t0 = seg.bus.now;
    const size_t before = seg.sent_by(src, static_cast<uint16_t>(0x180u + src)).size();
    seg.node(src).io.set_input(0, value);
    uint32_t waited = 0;
    while (seg.node(static_cast<uint8_t>(src + 1)).io.output(0) != value && waited < 2 * bound_us) {
      seg.bus.run_for(100);
      waited += 100;
    }
    ASSERT_EQ(seg.node(static_cast<uint8_t>(src + 1)).io.output(0), value) << "round " << round;
    const auto pdos = seg.sent_by(src, static_cast<uint16_t>(0x180u + src));
    ASSERT_EQ(pdos.size(), before + 1u);
    EXPECT_EQ(pdos.back().msg.data[0], value);
    EXPECT_LE(pdos.back().end_us - t0, bound_us) << "round " << round;
  }
  EXPECT_GT(seg.check_windows(), 20);
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(Polling, TimedAndSynchronousPdosLeaveOnlyInTheirWindow) {
  Segment seg(IdBits::k7, 15, false);
  seg.start(0);
  // Node 4: TPDO1 with a 10 ms event timer (due several times a cycle).
  // Node 9: TPDO1 synchronous, every 15th SYNC (once per poll cycle).
  const uint8_t timer_ms[2] = {10, 0};
  ASSERT_EQ(seg.node(4).io.od().write(0x1800, 5, timer_ms, 2), canopen::kSdoOk);
  const uint8_t every_15th = 15;
  ASSERT_EQ(seg.node(9).io.od().write(0x1800, 2, &every_15th, 1), canopen::kSdoOk);
  seg.nmt_start_all();
  seg.bus.run_for(100000);
  const uint32_t t0 = seg.bus.now;
  const uint16_t windows4 = seg.node(4).link.counters().windows;
  const uint16_t windows9 = seg.node(9).link.counters().windows;
  const size_t pdos4 = seg.sent_by(4, 0x184).size();
  const size_t pdos9 = seg.sent_by(9, 0x189).size();
  seg.bus.run_for(2000000);
  const size_t timed = seg.sent_by(4, 0x184).size() - pdos4;
  const size_t cycles4 = seg.node(4).link.counters().windows - windows4;
  // The timer falls due several times a cycle; the PDOs wait for the
  // window, where the newest of them leaves: one a window, and another when
  // the timer falls due again inside the window (W / 10 ms of them), never
  // outside it.
  EXPECT_GE(timed + 1u, cycles4);
  EXPECT_LE(timed, cycles4 + cycles4 * seg.config.window_us / 10000u + 2u);
  EXPECT_GE(cycles4, 2000000u / seg.cycle_bound_us() - 1u);
  const size_t synced = seg.sent_by(9, 0x189).size() - pdos9;
  const size_t cycles9 = seg.node(9).link.counters().windows - windows9;
  EXPECT_GE(synced + 1u, cycles9);
  EXPECT_LE(synced, cycles9 + 1u);
  EXPECT_EQ(seg.node(4).link.counters().overflow, 0);
  EXPECT_EQ(seg.node(9).link.counters().overflow, 0);
  EXPECT_GE(seg.check_windows(t0), static_cast<int>(timed + synced));
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(Polling, SdoExpeditedAndSegmentedUploadsFromAClient) {
  Segment seg(IdBits::k7, 15, false);
  seg.start(0);
  seg.bus.run_for(100000);
  // 1018h/1 (vendor id, 4 bytes: expedited) from node 7; 1008h (the device
  // name, 14 bytes: segmented) from node 12. Each equals the node's OD.
  const struct {
    uint8_t node;
    uint16_t index;
    uint8_t sub;
  } reads[] = {{7, 0x1018, 1}, {12, 0x1008, 0}};
  for (const auto& r : reads) {
    uint8_t buf[64] = {};
    uint8_t want[64] = {};
    uint16_t want_len = 0;
    ASSERT_EQ(seg.node(r.node).io.od().read(r.index, r.sub, want, sizeof want, &want_len), canopen::kSdoOk);
    ASSERT_EQ(seg.upload(r.node, r.index, r.sub, buf, sizeof buf), want_len) << std::hex << r.index;
    EXPECT_EQ(memcmp(buf, want, want_len), 0);
  }
  // Unused SDO bytes were left off on the line: responses shorter than 8
  // bytes (the expedited one ends in the vendor id, the last segment of
  // 1008h in its padding).
  bool short_sdo = false;
  for (const auto& m : seg.bus.log) {
    if ((m.can_id == 0x587 || m.can_id == 0x58C) && m.msg.length < 8) short_sdo = true;
  }
  EXPECT_TRUE(short_sdo);
  EXPECT_GT(seg.check_windows(), 10);
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(Polling, AMissingNodeOnlyLeavesItsWindowEmpty) {
  Segment seg(IdBits::k7, 6, false);
  seg.bring_up(100, false, 300000);
  seg.bus.detach(3);  // node 4 unplugged
  const uint16_t windows5 = seg.node(5).link.counters().windows;
  const uint32_t t_detach = seg.bus.now;
  seg.bus.run_for(500000);
  for (const auto& m : seg.bus.log) {
    if (m.talker == 3) {
      EXPECT_LE(static_cast<int32_t>(m.start_us - t_detach), 0) << "node 4 is gone";
    }
  }
  EXPECT_GE(seg.node(5).link.counters().windows - windows5, 500000u / seg.cycle_bound_us());
  EXPECT_GE(seg.sent_by(5, 0x705).size(), 7u);
  seg.check_windows();
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(Polling, AHeartbeatConsumerNoticesALostNodeAndSaysSoByEmcy) {
  Segment seg(IdBits::k7, 6, false);
  seg.start(100);
  // Node 2 watches node 3: 100 ms heartbeats wait up to a poll cycle for
  // their window, so the consumer allows 100 ms + 2 cycles.
  const uint32_t consumer_ms = 100u + 2u * seg.cycle_bound_us() / 1000u;
  uint8_t entry[4];
  canopen::put_le32(entry, (3u << 16) | consumer_ms);
  ASSERT_EQ(seg.node(2).io.od().write(0x1016, 1, entry, 4), canopen::kSdoOk);
  seg.nmt_start_all();
  seg.bus.run_for(1000000);
  EXPECT_TRUE(seg.sent_by(2, 0x082).empty()) << "no EMCY while node 3 beats";
  seg.bus.detach(2);  // node 3 unplugged
  const uint32_t t_detach = seg.bus.now;
  seg.bus.run_for(1000000);
  const auto emcy = seg.sent_by(2, 0x082);
  ASSERT_FALSE(emcy.empty());
  EXPECT_EQ(emcy[0].msg.length, 8);
  EXPECT_EQ(emcy[0].msg.data[0] | (emcy[0].msg.data[1] << 8), canopen::kEmcyLifeGuard);
  // Within the consumer time after node 3's last heartbeat, plus the wait
  // for node 2's window.
  EXPECT_LE(emcy[0].end_us - t_detach, consumer_ms * 1000u + seg.cycle_bound_us() + seg.config.window_us);
  // The others heard it (node 1's core got the EMCY frame).
  bool heard = false;
  for (const auto& r : seg.node(1).received) heard = heard || (r.second.id == 0x082 && r.second.dlc == 8);
  EXPECT_TRUE(heard);
  seg.check_windows();
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(Polling, ATalkerOutsideItsWindowCorruptsBothMessages) {
  Segment seg(IdBits::k7, 6, false);
  seg.bring_up(0, true, 200000);
  // Node 3 has a PDO waiting; the moment its window opens, node 5 blurts out
  // an NMT "reset node" for everybody (not its window).
  seg.node(3).io.set_input(0, 0x5A);
  for (int i = 0; i < 1000 && !seg.node(3).link.in_window(); ++i) seg.bus.run_for(50);
  ASSERT_TRUE(seg.node(3).link.in_window());
  ASSERT_EQ(seg.node(3).link.queued(), 0) << "its TPDO is on the line";
  uint8_t raw[serialnet::kMaxEncodedBytes];
  serialnet::SerialMessage reset = {};
  reset.id = 0;  // NMT
  reset.length = 2;
  reset.data[0] = canopen::kNmtResetNode;
  const uint8_t n = serialnet::encode(seg.config.set, reset, raw, sizeof raw);
  const serialnet::Decoder::Counters before = seg.node(1).link.decoder_counters();
  seg.bus.inject(4, std::vector<uint8_t>(raw, raw + n));
  seg.bus.run_for(100000);
  EXPECT_EQ(seg.bus.collisions, 1);
  // Neither arrived: no node reset (all still operational), node 4's output
  // did not follow; the receivers counted the damage.
  for (uint8_t id = 1; id <= 6; ++id) EXPECT_EQ(seg.node(id).node().nmt_state(), canopen::kNmtOperational);
  EXPECT_NE(seg.node(4).io.output(0), 0x5A);
  // (garbage without a flag is skipped; with one, it is a bad message).
  const serialnet::Decoder::Counters& c = seg.node(1).link.decoder_counters();
  EXPECT_GT(c.bad_crc + c.truncated + c.bad_length + c.bad_id + c.skipped_bytes,
            before.bad_crc + before.truncated + before.bad_length + before.bad_id + before.skipped_bytes);
  // Traffic goes on: the next change of node 3's input gets through.
  seg.node(3).io.set_input(0, 0x5B);
  seg.bus.run_for(200000);
  EXPECT_EQ(seg.node(4).io.output(0), 0x5B);
}

TEST(Polling, EachNodeGetsItsOwnWindowLength) {
  // Node 2 has a lot to say (a 12 ms window), the others 3.6 ms.
  static const uint32_t windows[6] = {3600, 12000, 3600, 3600, 3600, 3600};
  Segment seg(IdBits::k7, 6, false, 3600, windows);
  seg.bring_up(50, true, 300000);
  // The poller's SYNCs follow the table: SYNC(n + 1) leaves W_n after
  // SYNC(n) ended.
  const SerialBus::Sent* prev = nullptr;
  int checked = 0;
  for (const auto& m : seg.bus.log) {
    if (m.can_id != 0x080) continue;
    if (prev != nullptr) {
      EXPECT_EQ(m.start_us - prev->end_us, windows[prev->msg.data[0] - 1])
          << "after SYNC(" << int(prev->msg.data[0]) << ")";
      ++checked;
    }
    prev = &m;
  }
  EXPECT_GT(checked, 50);
  // Node 2 uses its long window: six EMCYs (an event each, none merged;
  // 13 bytes, 1131 µs on the line) leave in one window of 12 ms, where a
  // 3.6 ms window holds three.
  for (uint8_t k = 0; k < 6; ++k) {
    CanFrame f = {};
    f.id = 0x082;
    f.dlc = 8;
    f.data[0] = static_cast<uint8_t>(k + 1);
    ASSERT_TRUE(seg.node(2).link.send(f));
  }
  seg.bus.run_for(100000);
  const auto emcy = seg.sent_by(2, 0x082);
  ASSERT_EQ(emcy.size(), 6u);
  EXPECT_EQ(emcy.back().msg.data[0], 6);
  EXPECT_LE(emcy.back().end_us - emcy.front().start_us, windows[1]) << "all in one window";
  EXPECT_GE(seg.check_windows(), 50);
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(Polling, WorksInEveryConnectionSet) {
  check_every_connection_set(false);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
