// Seed 003's figure 7 in the simulator: two serial segments with 8-bit ids
// (segment A passing a token, segment B polled; three real I/O nodes each)
// on ONE simulated CAN bus (hil/sim/can_bus.h: bit-timed frames,
// arbitration, MCP2515 buffers) through two smart bridges with node-id
// offsets 32 and 48, plus a CAN master (an SDO client and NMT). The CAN side
// sees six ordinary CANopen nodes, 33-35 and 49-51; process data of a node
// on A reaches a node on B through both bridges within a bound derived from
// shared/timing/serial_segment.h.
//
// Why 48 and not 64: with the 8-bit set a segment's ids name serial nodes
// 1..31 only, so bridge B can carry into its segment only CAN node ids
// 49..79 and bridge A can put onto CAN only 33..63. A node of A reaches B by
// publishing under a serial node id of A whose CAN id falls in B's reach
// and is no node's own (here serial 25 of A = CAN node 57 = serial 9 of B):
// the two offsets must be less than 31 apart, their nodes apart.
//
// The segments and the CAN bus run in lockstep steps of kStepUs: a frame a
// bridge sends is queued on CAN at the end of the step it was sent in, and a
// frame CAN delivers reaches the bridge at the end of the step it arrived
// in. Both only delay (at most kStepUs each), so a measured latency is at
// most 2 kStepUs above the true one, and the check allows exactly that.
#include <gtest/gtest.h>
#include <stdint.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "canopen/sdo_client.h"
#include "serial_bus.h"
#include "serialnet/bridge.h"
#include "sim/can_bus.h"
#include "sim/event_queue.h"
#include "sim/rng.h"
#include "timing/can_bits.h"
#include "timing/serial_segment.h"
#include "timing/time_base.h"

namespace mb2co {
namespace test {
namespace {

using serialnet::Bridge;
using serialnet::BridgeConfig;

const uint32_t kStepUs = 10;
const uint32_t kCanBitrate = 500000;  // the Uno bridge's CAN rate
const uint8_t kNodes = 3;             // serial nodes 1..3 on each segment
const uint8_t kBridgeNode = 4;        // each bridge's own window
const uint8_t kOffsetA = 32;          // segment A: CAN nodes 33-35
const uint8_t kOffsetB = 48;          // segment B: CAN nodes 49-51
const uint32_t kWindowUs = 3600;
const uint32_t kGuardUs = 100;

// Process data across: serial node 1 of A (CAN node 33) publishes its TPDO1
// as serial node 25 of A, CAN 1B9h (node 57); bridge B forwards 1B9h into B
// as serial node 9's TPDO1 (189h on B's line), which serial node 1 of B
// (CAN node 49) consumes with its RPDO1.
const uint16_t kCrossTpdoOnA = 0x180 + 25;
const uint16_t kCrossOnCan = 0x180 + kOffsetA + 25;
const uint16_t kCrossOnB = 0x180 + (kOffsetA + 25 - kOffsetB);

serialnet::BusConfig segment_bus(bool token) {
  serialnet::BusConfig c = {};
  c.set = serialnet::connection_set(serialnet::IdBits::k8);
  c.baud = 115200;
  c.access = token ? serialnet::Access::kToken : serialnet::Access::kPolled;
  c.first_node = 1;
  c.last_node = kBridgeNode;
  c.window_us = kWindowUs;
  c.guard_us = kGuardUs;
  return c;
}

BridgeConfig bridge_config(bool token, uint8_t offset, const uint16_t* forward, uint8_t forward_count) {
  BridgeConfig b = {};
  b.bus = segment_bus(token);
  b.bus.access = token ? serialnet::Access::kTokenStarter : serialnet::Access::kPoller;
  b.bridge_node = kBridgeNode;
  b.node_offset = offset;
  b.extra_to_serial = forward;
  b.extra_count = forward_count;
  return b;
}

/// A bridge on its segment's line (a device of the serial bus) with a CAN
/// controller of its own on the shared CAN bus.
class CanBridge : public BusDevice {
 public:
  CanBridge(SerialBus& line, sim::CanBus& can, const BridgeConfig& config)
      : controller(can), bridge(config, line.port(kNodes), CanSink{&CanBridge::to_can, this}) {
    line.attach(kNodes, this);
  }

  sim::CanController controller;
  Bridge bridge;

  void on_byte(uint8_t byte, uint32_t byte_us) override { bridge.on_byte(byte, byte_us); }
  void process(uint32_t now_us) override { bridge.process(now_us); }
  void next_deadline(NextDeadline& d) const override { bridge.next_deadline(d); }
  /// What the controller received, to the bridge at `now_us`.
  void drain(uint32_t now_us) {
    CanFrame f;
    while (controller.receive(f)) bridge.on_can(f, now_us);
  }

 private:
  static bool to_can(void* ctx, const CanFrame& f) {
    return static_cast<CanBridge*>(ctx)->controller.send(f);
  }
};

/// One serial segment: three I/O nodes and its bridge.
struct BridgedSegment {
  BridgedSegment(bool token, sim::CanBus& can, const BridgeConfig& bridge_config)
      : line(serialnet::connection_set(serialnet::IdBits::k8), 115200), config(bridge_config) {
    for (uint8_t i = 0; i < kNodes; ++i)
      nodes.emplace_back(new Station(line, i, segment_bus(token), static_cast<uint8_t>(i + 1)));
    bridge.reset(new CanBridge(line, can, config));
  }
  SerialBus line;
  BridgeConfig config;
  std::vector<std::unique_ptr<Station>> nodes;
  std::unique_ptr<CanBridge> bridge;

  Station& node(uint8_t id) { return *nodes[id - 1u]; }
  uint8_t offset() const { return config.node_offset; }
};

/// A frame CAN delivered: who sent it (controller index) and when it ended.
struct OnCan {
  int sender;
  uint32_t end_us;
  CanFrame frame;
};

/// Figure 7: the segments, their bridges and a master on one CAN bus.
class Figure7 {
 public:
  Figure7() : can(queue, kCanBitrate, 7), master_port(can) {
    can.observer = [this](const sim::CanAttempt& a) {
      if (a.error) return;
      log.push_back(OnCan{a.sender, static_cast<uint32_t>(a.end_ns / sim::kNsPerUs), a.frame});
    };
  }

  sim::EventQueue queue;
  sim::CanBus can;
  sim::CanController master_port;
  canopen::SdoClient master{};
  bool master_on = false;
  std::vector<std::unique_ptr<BridgedSegment>> segments;
  std::vector<OnCan> log;
  uint32_t now = 0;  ///< virtual µs, the same on both lines and on CAN

  /// Joins a segment behind a bridge with `offset`; false (nothing joins)
  /// when the bridge is refused: its own settings, or CAN node ids that a
  /// bridge already on the bus gives its nodes.
  bool add_segment(bool token, uint8_t offset, const uint16_t* forward = nullptr, uint8_t forward_count = 0) {
    const BridgeConfig config = bridge_config(token, offset, forward, forward_count);
    if (serialnet::check_bridge_config(config) != serialnet::BridgeConfigError::kOk) return false;
    for (const auto& s : segments) {
      if (serialnet::bridges_clash(s->config, config)) return false;
    }
    segments.emplace_back(new BridgedSegment(token, can, config));
    return true;
  }

  BridgedSegment& segment(size_t i) { return *segments[i]; }

  /// Power-on of every serial node with 1019h = the windows per cycle (a
  /// poll carries its counter) and a 100 ms heartbeat.
  void power_on() {
    for (auto& s : segments) {
      for (auto& n : s->nodes) {
        n->node().start(n->link.node_id(), now);
        const uint8_t windows = kBridgeNode;
        ASSERT_EQ(n->io.od().write(0x1019, 0, &windows, 1), canopen::kSdoOk);
        const uint8_t hb[2] = {100, 0};
        ASSERT_EQ(n->io.od().write(0x1017, 0, hb, 2), canopen::kSdoOk);
      }
    }
  }

  /// Runs every line and the CAN bus in lockstep to now + `us`.
  void run_for(uint32_t us) {
    const uint32_t until = now + us;
    while (now != until) {
      const uint32_t t = std::min(now + kStepUs, until);
      queue.run_until(static_cast<sim::SimNs>(t) * sim::kNsPerUs);
      for (auto& s : segments) s->line.run_until(t);
      now = t;
      for (auto& s : segments) s->bridge->drain(now);
      CanFrame f;
      while (master_port.receive(f)) {
        if (master_on) master.on_frame(f, now, master_sink());
      }
      if (master_on) master.process(now, master_sink());
    }
  }

  void send(const CanFrame& f) { ASSERT_TRUE(master_port.send(f)); }
  void nmt(uint8_t command, uint8_t can_node) {
    CanFrame f = {};
    f.dlc = 2;
    f.data[0] = command;
    f.data[1] = can_node;
    send(f);
  }

  /// The master's SDO upload from CAN node `can_node`; -1: failed.
  int upload(uint8_t can_node, uint16_t index, uint8_t sub, uint8_t* buf, uint32_t capacity) {
    master_on = true;
    master.init(can_node);
    if (!master.start_upload(index, sub, canopen::kSdoAuto, buf, capacity, now, master_sink())) return -1;
    for (int i = 0; i < 2000 && master.busy(); ++i) run_for(1000);
    if (master.status() != canopen::SdoClient::kDone) return -1;
    return static_cast<int>(master.transferred());
  }

  int collisions() const {
    int n = 0;
    for (const auto& s : segments) n += s->line.collisions;
    return n;
  }

 private:
  static bool to_master_port(void* ctx, const CanFrame& f) {
    return static_cast<Figure7*>(ctx)->master_port.send(f);
  }
  CanSink master_sink() { return CanSink{&Figure7::to_master_port, this}; }
};

/// Segment A (token passing, offset 32) and segment B (polled, offset 48,
/// forwarding the crossing TPDO), powered on.
class TwoBridges : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(net.add_segment(true, kOffsetA));
    ASSERT_TRUE(net.add_segment(false, kOffsetB, &kCrossOnCan, 1));
    net.power_on();
  }
  BridgedSegment& a() { return net.segment(0); }
  BridgedSegment& b() { return net.segment(1); }

  Figure7 net;
};

TEST_F(TwoBridges, EveryNodeBootsAndBeatsAtItsOffsetIdAndNoIdIsClaimedTwice) {
  net.run_for(1000000);
  std::map<uint32_t, std::set<int>> senders;  // CAN id -> controllers that sent it
  for (const OnCan& e : net.log) senders[e.frame.id].insert(e.sender);
  for (size_t s = 0; s < net.segments.size(); ++s) {
    BridgedSegment& seg = net.segment(s);
    for (uint8_t n = 1; n <= kNodes; ++n) {
      const uint32_t id = 0x700u + seg.offset() + n;
      std::vector<CanFrame> beats;
      for (const OnCan& e : net.log) {
        if (e.frame.id == id) beats.push_back(e.frame);
      }
      ASSERT_GE(beats.size(), 5u) << "CAN node " << int(seg.offset() + n);
      EXPECT_EQ(beats.front().data[0], canopen::kNmtInitialising) << "boot-up first";
      EXPECT_EQ(beats.back().data[0], canopen::kNmtPreOperational) << "then heartbeats";
      EXPECT_EQ(senders[id], std::set<int>{seg.bridge->controller.index()}) << "only its own bridge";
      EXPECT_EQ(senders.count(0x700u + n), 0u) << "no node id without its offset";
    }
    EXPECT_EQ(seg.bridge->bridge.counters().overflow, 0u);
    EXPECT_GT(seg.bridge->bridge.counters().polls, 0u);
  }
  // Six heartbeat ids, each from one bridge; no segment poll reached CAN.
  int beating = 0;
  for (const auto& e : senders) {
    EXPECT_EQ(e.second.size(), 1u) << std::hex << e.first << "h sent by two controllers";
    if (e.first >= 0x701u && e.first <= 0x77Fu) ++beating;
  }
  EXPECT_EQ(beating, 2 * kNodes);
  EXPECT_EQ(senders.count(0x080u), 0u);
  EXPECT_EQ(net.can.error_frames(), 0u);
  EXPECT_EQ(net.collisions(), 0);
}

TEST_F(TwoBridges, MasterUploadsFromEachOfTheSixNodesByItsCanId) {
  net.run_for(500000);
  for (size_t s = 0; s < net.segments.size(); ++s) {
    BridgedSegment& seg = net.segment(s);
    for (uint8_t n = 1; n <= kNodes; ++n) {
      // The product code as the node holds it, answered at 580h + its CAN id
      // by its own bridge.
      uint8_t got[4] = {};
      const uint8_t can_node = static_cast<uint8_t>(seg.offset() + n);
      ASSERT_EQ(net.upload(can_node, 0x1018, 2, got, sizeof got), 4) << "CAN node " << int(can_node);
      uint8_t held[4] = {};
      uint16_t size = 0;
      ASSERT_EQ(seg.node(n).io.od().read(0x1018, 2, held, sizeof held, &size), canopen::kSdoOk);
      EXPECT_EQ(std::memcmp(got, held, 4), 0);
      bool answered_at_its_id = false;
      for (const OnCan& e : net.log) {
        answered_at_its_id |= e.frame.id == 0x580u + can_node && e.sender == seg.bridge->controller.index();
      }
      EXPECT_TRUE(answered_at_its_id) << "CAN node " << int(can_node);
    }
    // Segmented, several request/response pairs through the bridge.
    char name[32] = {};
    const uint8_t can_node = static_cast<uint8_t>(seg.offset() + 2);
    EXPECT_EQ(net.upload(can_node, 0x1008, 0, reinterpret_cast<uint8_t*>(name), sizeof name - 1),
              static_cast<int>(std::strlen("mb2co I/O node")));
    EXPECT_STREQ(name, "mb2co I/O node");
  }
  EXPECT_EQ(net.collisions(), 0);
}

TEST_F(TwoBridges, NmtToOneCanIdReachesExactlyThatSerialNode) {
  net.run_for(300000);
  auto states = [this]() {
    std::vector<uint8_t> out;
    for (auto& s : net.segments) {
      for (auto& n : s->nodes) out.push_back(n->node().nmt_state());
    }
    return out;
  };
  const uint8_t pre = canopen::kNmtPreOperational;
  ASSERT_EQ(states(), std::vector<uint8_t>(2 * kNodes, pre));
  net.nmt(canopen::kNmtStart, kOffsetB + 2);  // CAN node 50: serial node 2 of B
  net.run_for(100000);
  EXPECT_EQ(states(), (std::vector<uint8_t>{pre, pre, pre, pre, canopen::kNmtOperational, pre}));
  net.nmt(canopen::kNmtStop, kOffsetA + 2);  // CAN node 34: serial node 2 of A
  net.run_for(100000);
  EXPECT_EQ(states(),
            (std::vector<uint8_t>{pre, canopen::kNmtStopped, pre, pre, canopen::kNmtOperational, pre}));
  // Node 2 of either segment without an offset is no node of theirs.
  net.nmt(canopen::kNmtStart, 2);
  net.run_for(100000);
  EXPECT_EQ(states(),
            (std::vector<uint8_t>{pre, canopen::kNmtStopped, pre, pre, canopen::kNmtOperational, pre}));
  EXPECT_EQ(net.collisions(), 0);
}

/// L <= A's TPDO (token round + own message) + CAN (one longest frame in
/// progress, then its own; nothing of higher priority is sent meanwhile) +
/// B's bridge window (a poll cycle + the message) + the lockstep's 2 steps.
uint32_t crossing_bound_us(const serialnet::BusConfig& a, const serialnet::BusConfig& b) {
  const timing::SerialLatency on_a = timing::serial_latency(a, 1, 2, nullptr, 0, 0);
  const timing::SerialLatency on_b = timing::can_to_serial(b, kBridgeNode, 2, nullptr, 0, 0);
  EXPECT_TRUE(on_a.fits && on_b.fits);
  const uint64_t blocking_ns =
      timing::bits_to_ns_ceil(timing::frame_bits_worst(false, 8, timing::WorstCase::kDavis), kCanBitrate);
  return timing::serial_to_can_us(on_a, 0, kCanBitrate, 2) +
         static_cast<uint32_t>((blocking_ns + 999u) / 1000u) + on_b.worst_us + 2 * kStepUs;
}

TEST_F(TwoBridges, ProcessDataCrossesFromSegmentAToSegmentBWithinItsBound) {
  // Node 33 publishes as serial node 25 of A (disable the TPDO, set its id);
  // node 49 consumes what B's line carries as serial node 9's TPDO1.
  uint8_t v[4];
  canopen::ObjectDictionary& producer = a().node(1).io.od();
  canopen::put_le32(v, 0x80000000u | 0x181u);
  ASSERT_EQ(producer.write(0x1800, 1, v, 4), canopen::kSdoOk);
  canopen::put_le32(v, kCrossTpdoOnA);
  ASSERT_EQ(producer.write(0x1800, 1, v, 4), canopen::kSdoOk);
  canopen::ObjectDictionary& consumer = b().node(1).io.od();
  canopen::put_le32(v, 0x80000000u | 0x201u);
  ASSERT_EQ(consumer.write(0x1400, 1, v, 4), canopen::kSdoOk);
  canopen::put_le32(v, kCrossOnB);
  ASSERT_EQ(consumer.write(0x1400, 1, v, 4), canopen::kSdoOk);
  net.run_for(300000);
  net.nmt(canopen::kNmtStart, kOffsetA + 1);
  net.nmt(canopen::kNmtStart, kOffsetB + 1);
  net.run_for(200000);

  // Each new input at a random moment of A's round; measured from the
  // moment node 33's core queued its TPDO to the end of the last byte of
  // the forwarded message on B's line (when node 49 has it).
  uint32_t queued_us = 0;
  bool queued = false;
  a().node(1).on_queued = [&](const CanFrame& f, uint32_t now_us) {
    if (f.id == kCrossTpdoOnA && !queued) {
      queued = true;
      queued_us = now_us;
    }
  };
  const uint32_t bound_us = crossing_bound_us(segment_bus(true), segment_bus(false));
  sim::Rng rng(27);
  const int kChanges = 60;
  uint32_t worst_us = 0;
  uint64_t sum_us = 0;
  for (int k = 0; k < kChanges; ++k) {
    net.run_for(static_cast<uint32_t>(rng.range(1, timing::poll_cycle_us(segment_bus(false)))));
    const uint8_t value = static_cast<uint8_t>(k + 1);
    queued = false;
    b().node(1).received.clear();
    a().node(1).io.set_input(0, value);
    uint32_t arrived_us = 0;
    for (uint32_t waited = 0; waited <= bound_us + 100000 && arrived_us == 0; waited += 1000) {
      net.run_for(1000);
      for (const auto& r : b().node(1).received) {
        if (r.second.id == kCrossOnB && r.second.data[0] == value && arrived_us == 0) arrived_us = r.first;
      }
    }
    ASSERT_TRUE(queued) << "change " << k << ": node 33 queued no TPDO";
    ASSERT_NE(arrived_us, 0u) << "change " << k << ": never reached node 49";
    const uint32_t latency_us = arrived_us - queued_us;
    EXPECT_LE(latency_us, bound_us) << "change " << k;
    EXPECT_EQ(b().node(1).io.output(0), value);
    worst_us = std::max(worst_us, latency_us);
    sum_us += latency_us;
  }
  // The figure docs/serial-canopen.md quotes.
  std::printf("crossing,changes=%d,latency_max_us=%u,latency_mean_us=%u,bound_us=%u\n", kChanges, worst_us,
              static_cast<unsigned>(sum_us / kChanges), bound_us);
  EXPECT_EQ(net.collisions(), 0);
  EXPECT_EQ(b().bridge->bridge.counters().overflow, 0u);
}

TEST_F(TwoBridges, ABridgeWhoseNodesWouldShareCanIdsIsRefused) {
  // Offset 34 puts serial nodes 1-3 at CAN 35-37: 35 is node 3 of A.
  EXPECT_FALSE(net.add_segment(false, 34));
  EXPECT_FALSE(net.add_segment(false, 47)) << "48-50: 49 and 50 are B's";
  // Offset 33 puts them at 34-36: 34 and 35 are A's (36, A's window, is no node).
  EXPECT_FALSE(net.add_segment(false, 33));
  // Offset 62: 63-65, nobody's yet.
  EXPECT_TRUE(net.add_segment(false, 62));
  EXPECT_EQ(net.segments.size(), 3u);
}

TEST(BridgesClash, NodeRangesOverlapNotTheBridgesOwnWindows) {
  const BridgeConfig a = bridge_config(false, 32, nullptr, 0);  // nodes at 33-35, window 36
  EXPECT_TRUE(serialnet::bridges_clash(a, bridge_config(false, 32, nullptr, 0)));
  EXPECT_TRUE(serialnet::bridges_clash(a, bridge_config(false, 34, nullptr, 0)));
  EXPECT_TRUE(serialnet::bridges_clash(a, bridge_config(false, 30, nullptr, 0)));
  EXPECT_TRUE(serialnet::bridges_clash(bridge_config(false, 30, nullptr, 0), a)) << "symmetric";
  EXPECT_FALSE(serialnet::bridges_clash(a, bridge_config(false, 35, nullptr, 0))) << "36-38: 36 is no node";
  EXPECT_FALSE(serialnet::bridges_clash(a, bridge_config(false, 29, nullptr, 0))) << "30-32";
  EXPECT_FALSE(serialnet::bridges_clash(a, bridge_config(false, kOffsetB, nullptr, 0)));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
