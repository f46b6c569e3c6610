// The smart bridge (shared/serialnet/bridge.h) between a segment of three
// real I/O nodes on the virtual serial line and a virtual CAN bus: the CAN
// side sees the serial nodes as ordinary CANopen nodes at node id + offset,
// and the segment gets only what its nodes consume.
#include <gtest/gtest.h>
#include <stdint.h>

#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include "canopen/sdo_client.h"
#include "serial_bus.h"
#include "serialnet/bridge.h"

namespace mb2co {
namespace test {
namespace {

using serialnet::Bridge;
using serialnet::BridgeConfig;

const uint8_t kOffset = 0x20;   // serial node n is CAN node 0x20 + n
const uint8_t kNodes = 3;       // serial nodes 1..3
const uint8_t kBridgeNode = 4;  // the bridge's own window

/// The bridge on the line (talker kNodes) and the CAN bus beside it: what
/// the bridge puts on CAN is logged with its time; a CAN-side SDO client (a
/// master) hears it one pass later, as over a real bus.
class BridgeDevice : public BusDevice {
  SerialBus& bus_;  // first: the bridge's port comes from it

 public:
  BridgeDevice(SerialBus& bus, const BridgeConfig& config)
      : bus_(bus), bridge(config, bus.port(kNodes), CanSink{&BridgeDevice::on_can_frame, this}) {
    bus.attach(kNodes, this);
  }

  std::vector<std::pair<uint32_t, CanFrame>> can_log;  ///< frames the bridge put on CAN
  bool can_refuses = false;                            ///< the CAN port's queue is full
  canopen::SdoClient master{};
  bool master_on = false;

  /// Master's frames onto CAN: the bridge hears them.
  CanSink can_sink() { return CanSink{&BridgeDevice::from_master, this}; }
  void can_send(const CanFrame& f) { bridge.on_can(f, bus_.now); }

  void on_byte(uint8_t byte, uint32_t byte_us) override { bridge.on_byte(byte, byte_us); }
  void process(uint32_t now_us) override {
    std::vector<CanFrame> heard;
    heard.swap(to_master_);
    if (master_on) {
      for (const CanFrame& f : heard) master.on_frame(f, now_us, can_sink());
      master.process(now_us, can_sink());
    }
    bridge.process(now_us);
  }
  void next_deadline(NextDeadline& d) const override {
    if (!to_master_.empty()) d.now();
    if (master_on) master.next_deadline(d);
    bridge.next_deadline(d);
  }

  Bridge bridge;

  std::vector<CanFrame> on_can_with_id(uint32_t id) const {
    std::vector<CanFrame> out;
    for (const auto& e : can_log) {
      if (e.second.id == id) out.push_back(e.second);
    }
    return out;
  }

 private:
  static bool on_can_frame(void* ctx, const CanFrame& f) {
    BridgeDevice& d = *static_cast<BridgeDevice*>(ctx);
    if (d.can_refuses) return false;
    d.can_log.emplace_back(d.bus_.now, f);
    d.to_master_.push_back(f);
    return true;
  }
  static bool from_master(void* ctx, const CanFrame& f) {
    static_cast<BridgeDevice*>(ctx)->can_send(f);
    return true;
  }

  std::vector<CanFrame> to_master_;
};

CanFrame frame(uint32_t id, std::initializer_list<uint8_t> bytes) {
  CanFrame f = {};
  f.id = id;
  for (uint8_t b : bytes) f.data[f.dlc++] = b;
  return f;
}

/// Three I/O nodes and the bridge on one 8-bit segment, polled by the bridge
/// or passing a token the bridge starts.
class BridgedSegment {
 public:
  explicit BridgedSegment(bool token, const uint16_t* extra = nullptr, uint8_t extra_count = 0,
                          serialnet::IdBits bits = serialnet::IdBits::k8)
      : bus(serialnet::connection_set(bits), 115200) {
    serialnet::BusConfig c = {};
    c.set = serialnet::connection_set(bits);
    c.baud = 115200;
    c.first_node = 1;
    c.last_node = kBridgeNode;
    c.window_us = 3600;
    c.guard_us = 100;
    for (uint8_t i = 0; i < kNodes; ++i) {
      serialnet::BusConfig node_config = c;
      node_config.access = token ? serialnet::Access::kToken : serialnet::Access::kPolled;
      stations.emplace_back(new Station(bus, i, node_config, static_cast<uint8_t>(i + 1)));
    }
    BridgeConfig b = {};
    b.bus = c;
    b.bus.access = token ? serialnet::Access::kTokenStarter : serialnet::Access::kPoller;
    b.bridge_node = kBridgeNode;
    b.node_offset = kOffset;
    b.extra_to_serial = extra;
    b.extra_count = extra_count;
    EXPECT_EQ(serialnet::check_bridge_config(b), serialnet::BridgeConfigError::kOk);
    bridge.reset(new BridgeDevice(bus, b));
  }

  SerialBus bus;
  std::vector<std::unique_ptr<Station>> stations;
  std::unique_ptr<BridgeDevice> bridge;

  Station& node(uint8_t id) { return *stations[id - 1u]; }
  const Bridge::Counters& counters() const { return bridge->bridge.counters(); }

  /// Power-on with a 100 ms heartbeat and 1019h = windows per cycle (a poll
  /// SYNC carries its counter), then `settle_us` of running.
  void power_on(uint32_t settle_us = 500000) {
    for (auto& s : stations) {
      s->node().start(s->link.node_id(), bus.now);
      const uint8_t overflow = kBridgeNode;
      ASSERT_EQ(s->io.od().write(0x1019, 0, &overflow, 1), canopen::kSdoOk);
      const uint8_t hb[2] = {100, 0};
      ASSERT_EQ(s->io.od().write(0x1017, 0, hb, 2), canopen::kSdoOk);
    }
    bus.run_for(settle_us);
  }

  /// A CAN-side master's SDO upload from CAN node `can_node`; -1: failed.
  int upload(uint8_t can_node, uint16_t index, uint8_t sub, uint8_t* buf, uint32_t capacity) {
    BridgeDevice& b = *bridge;
    b.master_on = true;
    b.master.init(can_node);
    if (!b.master.start_upload(index, sub, canopen::kSdoAuto, buf, capacity, bus.now, b.can_sink()))
      return -1;
    for (int i = 0; i < 2000 && b.master.busy(); ++i) bus.run_for(1000);
    if (b.master.status() != canopen::SdoClient::kDone) return -1;
    return static_cast<int>(b.master.transferred());
  }
};

void expect_nodes_seen_on_can(bool token) {
  BridgedSegment seg(token);
  seg.power_on(1000000);
  for (uint8_t n = 1; n <= kNodes; ++n) {
    const std::vector<CanFrame> beats = seg.bridge->on_can_with_id(0x700u + kOffset + n);
    ASSERT_GE(beats.size(), 5u) << "node " << int(n);
    EXPECT_EQ(beats[0].dlc, 1);
    EXPECT_EQ(beats[0].data[0], canopen::kNmtInitialising) << "boot-up first";
    EXPECT_EQ(beats.back().data[0], canopen::kNmtPreOperational) << "then heartbeats";
    EXPECT_TRUE(seg.bridge->on_can_with_id(0x700u + n).empty()) << "no id without its offset";
  }
  for (const auto& e : seg.bridge->can_log) EXPECT_NE(e.second.id, 0x080u) << "a poll reached CAN";
  EXPECT_GT(seg.counters().polls, 0u);
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(Bridge, PolledNodesBootAndBeatOnCanAtTheirOffsetIds) {
  expect_nodes_seen_on_can(false);
}
TEST(Bridge, TokenRingNodesBootAndBeatOnCanAtTheirOffsetIds) {
  expect_nodes_seen_on_can(true);
}

void expect_sdo_uploads_through_bridge(bool token) {
  BridgedSegment seg(token);
  seg.power_on();
  for (uint8_t n = 1; n <= kNodes; ++n) {
    uint8_t buf[4] = {};
    ASSERT_EQ(seg.upload(static_cast<uint8_t>(kOffset + n), 0x1018, 2, buf, sizeof buf), 4) << int(n);
    uint8_t expected[4] = {};
    uint16_t size = 0;
    ASSERT_EQ(seg.node(n).io.od().read(0x1018, 2, expected, sizeof expected, &size), canopen::kSdoOk);
    EXPECT_EQ(std::memcmp(buf, expected, 4), 0);
    EXPECT_FALSE(seg.bridge->on_can_with_id(0x580u + kOffset + n).empty()) << "answered at its CAN id";
  }
  // Segmented: the device name, several request/response pairs through the bridge.
  char name[32] = {};
  const int got = seg.upload(kOffset + 2, 0x1008, 0, reinterpret_cast<uint8_t*>(name), sizeof name - 1);
  EXPECT_STREQ(name, "mb2co I/O node");
  EXPECT_EQ(got, static_cast<int>(std::strlen("mb2co I/O node")));
  EXPECT_EQ(seg.bus.collisions, 0);
}

TEST(Bridge, CanMasterUploadsFromEachPolledNode) {
  expect_sdo_uploads_through_bridge(false);
}
TEST(Bridge, CanMasterUploadsFromEachTokenRingNode) {
  expect_sdo_uploads_through_bridge(true);
}

TEST(Bridge, NmtTargetIsTranslatedAndOtherNodesCommandsStayOnCan) {
  BridgedSegment seg(false);
  seg.power_on();
  seg.bridge->can_send(frame(0x000, {canopen::kNmtStart, kOffset + 2}));
  seg.bus.run_for(100000);
  EXPECT_EQ(seg.node(2).node().nmt_state(), canopen::kNmtOperational);
  EXPECT_EQ(seg.node(1).node().nmt_state(), canopen::kNmtPreOperational);
  EXPECT_EQ(seg.node(3).node().nmt_state(), canopen::kNmtPreOperational);

  // Node 1 and node kBridgeNode + offset are not serial nodes: nothing goes out.
  const uint16_t before = seg.counters().not_consumed;
  seg.bridge->can_send(frame(0x000, {canopen::kNmtStart, 1}));
  seg.bridge->can_send(frame(0x000, {canopen::kNmtStart, kOffset + kBridgeNode}));
  seg.bus.run_for(100000);
  EXPECT_EQ(seg.counters().not_consumed, before + 2u);
  EXPECT_EQ(seg.node(1).node().nmt_state(), canopen::kNmtPreOperational);

  seg.bridge->can_send(frame(0x000, {canopen::kNmtStart, 0}));  // all nodes
  seg.bus.run_for(100000);
  for (uint8_t n = 1; n <= kNodes; ++n) EXPECT_EQ(seg.node(n).node().nmt_state(), canopen::kNmtOperational);
}

TEST(Bridge, CanSyncNeverReachesTheSegment) {
  BridgedSegment seg(false);
  seg.power_on();
  const size_t logged = seg.bus.log.size();
  for (int i = 0; i < 5; ++i) {
    seg.bridge->can_send(frame(0x080, {}));
    seg.bus.run_for(20000);
  }
  EXPECT_EQ(seg.counters().can_syncs, 5u);
  // Every SYNC on the line since is a poll from the bridge: counter byte = a window owner.
  for (size_t i = logged; i < seg.bus.log.size(); ++i) {
    const SerialBus::Sent& m = seg.bus.log[i];
    if (m.can_id != 0x080) continue;
    EXPECT_EQ(m.talker, kNodes);
    ASSERT_EQ(m.msg.length, 1);
    EXPECT_GE(m.msg.data[0], 1);
    EXPECT_LE(m.msg.data[0], kBridgeNode);
  }
}

TEST(Bridge, ProcessDataCrossesBothWays) {
  BridgedSegment seg(false);
  seg.power_on();
  seg.bridge->can_send(frame(0x000, {canopen::kNmtStart, 0}));
  seg.bus.run_for(100000);

  // RPDO1 of serial node 3 from CAN.
  seg.bridge->can_send(frame(0x200u + kOffset + 3, {0x5A, 0xA5}));
  // The same function for a CAN node below the offset: not the segment's.
  seg.bridge->can_send(frame(0x200u + 3, {0x11, 0x11}));
  seg.bus.run_for(100000);
  EXPECT_EQ(seg.node(3).io.output(0), 0x5A);
  EXPECT_EQ(seg.node(3).io.output(1), 0xA5);
  EXPECT_GE(seg.counters().not_consumed, 1u);

  // TPDO1 of serial node 1 onto CAN.
  seg.node(1).io.set_input(0, 0x42);
  seg.bus.run_for(100000);
  const std::vector<CanFrame> tpdos = seg.bridge->on_can_with_id(0x180u + kOffset + 1);
  ASSERT_FALSE(tpdos.empty());
  EXPECT_EQ(tpdos.back().data[0], 0x42);
}

TEST(Bridge, ExtraRouteCarriesACanNodesTpdoToTheSerialRpdoThatConsumesIt) {
  const uint16_t can_tpdo = 0x180u + kOffset + 9;  // a CAN node in the offset range
  for (bool listed : {false, true}) {
    BridgedSegment seg(false, listed ? &can_tpdo : nullptr, listed ? 1 : 0);
    seg.power_on();
    // Node 2's RPDO1 consumes the CAN node's TPDO1 (as the segment sees it: node 9).
    uint8_t b[4];
    canopen::put_le32(b, 0x80000000u | 0x202u);
    ASSERT_EQ(seg.node(2).io.od().write(0x1400, 1, b, 4), canopen::kSdoOk);
    canopen::put_le32(b, 0x180u + 9);
    ASSERT_EQ(seg.node(2).io.od().write(0x1400, 1, b, 4), canopen::kSdoOk);
    seg.bridge->can_send(frame(0x000, {canopen::kNmtStart, 0}));
    seg.bus.run_for(100000);
    seg.bridge->can_send(frame(can_tpdo, {0x77, 0}));
    seg.bus.run_for(100000);
    EXPECT_EQ(seg.node(2).io.output(0), listed ? 0x77 : 0x00) << listed;
  }
}

TEST(Bridge, FunctionsTheSetCannotCarryAreDroppedAndCounted) {
  BridgedSegment seg(false);
  seg.power_on();
  CanFrame rtr = frame(0x180u + kOffset + 1, {});
  rtr.flags = CanFrame::kRtr;
  seg.bridge->can_send(rtr);
  CanFrame ext = frame(0x600u + kOffset + 1, {0x40, 0x18, 0x10, 1, 0, 0, 0, 0});
  ext.flags = CanFrame::kExtended;
  seg.bridge->can_send(ext);
  // TPDO3 of a serial node: an id a serial node produces, never consumes.
  seg.bridge->can_send(frame(0x380u + kOffset + 1, {1}));
  // TIME: no serial node here consumes it.
  seg.bridge->can_send(frame(0x100, {1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(seg.counters().unmappable, 2u);
  EXPECT_EQ(seg.counters().not_consumed, 2u);
  EXPECT_EQ(seg.counters().to_serial, 0u);
}

TEST(Bridge, RefusedFramesWaitInOrderAndOverflowIsCounted) {
  BridgedSegment seg(false);
  // The CAN port refuses: the boot-ups wait in the bridge.
  seg.bridge->can_refuses = true;
  seg.power_on(50000);
  EXPECT_TRUE(seg.bridge->can_log.empty());
  EXPECT_EQ(seg.bridge->bridge.waiting_to_can(), kNodes);
  seg.bridge->can_refuses = false;
  seg.bus.run_for(2000);
  ASSERT_GE(seg.bridge->can_log.size(), static_cast<size_t>(kNodes));
  for (uint8_t n = 1; n <= kNodes; ++n) {
    EXPECT_EQ(seg.bridge->can_log[n - 1u].second.id, 0x700u + kOffset + n) << "in the order heard";
    EXPECT_EQ(seg.bridge->can_log[n - 1u].second.data[0], canopen::kNmtInitialising);
  }

  // 20 NMT commands at once: the link's queue takes 8, the bridge's 8, the
  // rest are dropped and counted; the 16 reach the line in the bridge's windows.
  const size_t logged = seg.bus.log.size();
  for (int i = 0; i < 20; ++i) seg.bridge->can_send(frame(0x000, {canopen::kNmtEnterPreOperational, 0}));
  EXPECT_EQ(seg.counters().overflow, 4u);
  seg.bus.run_for(200000);
  int nmt_on_line = 0;
  for (size_t i = logged; i < seg.bus.log.size(); ++i) {
    if (seg.bus.log[i].can_id == 0x000 && seg.bus.log[i].talker == kNodes) ++nmt_on_line;
  }
  EXPECT_EQ(nmt_on_line, 16);
  EXPECT_EQ(seg.counters().to_serial, 16u);
  EXPECT_EQ(seg.bridge->bridge.waiting_to_serial(), 0u);
}

TEST(Bridge, ConfigChecks) {
  BridgeConfig b = {};
  b.bus.set = serialnet::connection_set(serialnet::IdBits::k7);
  b.bus.baud = 115200;
  b.bus.access = serialnet::Access::kPoller;
  b.bus.first_node = 1;
  b.bus.last_node = 4;
  b.bus.window_us = 3600;
  b.bus.guard_us = 100;
  b.bridge_node = 4;
  b.node_offset = 100;
  EXPECT_EQ(serialnet::check_bridge_config(b), serialnet::BridgeConfigError::kOk);
  BridgeConfig c = b;
  c.bus.access = serialnet::Access::kPolled;
  EXPECT_EQ(serialnet::check_bridge_config(c), serialnet::BridgeConfigError::kAccess);
  c = b;
  c.bridge_node = 5;
  EXPECT_EQ(serialnet::check_bridge_config(c), serialnet::BridgeConfigError::kBridgeNode);
  c = b;
  c.node_offset = 124;
  EXPECT_EQ(serialnet::check_bridge_config(c), serialnet::BridgeConfigError::kOffset);
  c = b;
  c.bus.last_node = 16;  // the 7-bit set has 15 nodes
  EXPECT_EQ(serialnet::check_bridge_config(c), serialnet::BridgeConfigError::kBus);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
