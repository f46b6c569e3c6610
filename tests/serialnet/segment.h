// A segment of real I/O nodes (shared/ionode: the unchanged node core) on the
// virtual serial line, configured for polling or token passing, and the
// checks every test of bus access shares: who talked when.
#pragma once
#include <gtest/gtest.h>
#include <stdint.h>

#include <memory>
#include <vector>

#include "serial_bus.h"

namespace mb2co {
namespace test {

/// Station i (index) is node i + 1. Station 0 is the poller (polling) or
/// the token starter (token passing), and has the SDO client.
class Segment {
 public:
  Segment(serialnet::IdBits bits, uint8_t nodes, bool token, uint32_t window_us = 2500,
          uint32_t guard_us = 100, uint32_t baud = 115200)
      : bus(serialnet::connection_set(bits), baud) {
    config.set = serialnet::connection_set(bits);
    config.baud = baud;
    config.first_node = 1;
    config.last_node = nodes;
    config.window_us = window_us;
    config.guard_us = guard_us;
    config.max_gap_us = 0;
    for (uint8_t i = 0; i < nodes; ++i) {
      serialnet::BusConfig c = config;
      if (token) {
        c.access = i == 0 ? serialnet::Access::kTokenStarter : serialnet::Access::kToken;
      } else {
        c.access = i == 0 ? serialnet::Access::kPoller : serialnet::Access::kPolled;
      }
      stations.emplace_back(new Station(bus, i, c, static_cast<uint8_t>(i + 1)));
    }
    token_ = token;
  }

  SerialBus bus;
  serialnet::BusConfig config = {};
  std::vector<std::unique_ptr<Station>> stations;

  Station& node(uint8_t id) { return *stations[id - 1u]; }
  uint8_t count() const { return static_cast<uint8_t>(stations.size()); }

  /// Power-on of every node at now, with what a serial segment needs in the
  /// OD: 1019h = the number of nodes (the SYNC carries the counter that polls
  /// them; 0 would make every poll a SYNC length error) and a heartbeat.
  void start(uint16_t heartbeat_ms = 200) {
    for (auto& s : stations) {
      s->node().start(s->link.node_id(), bus.now);
      const uint8_t overflow = count();
      ASSERT_EQ(s->io.od().write(0x1019, 0, &overflow, 1), canopen::kSdoOk);
      const uint8_t hb[2] = {static_cast<uint8_t>(heartbeat_ms), static_cast<uint8_t>(heartbeat_ms >> 8)};
      ASSERT_EQ(s->io.od().write(0x1017, 0, hb, 2), canopen::kSdoOk);
    }
  }

  /// NMT start of all nodes, sent by station 0 on the line (and obeyed by
  /// its own node, which does not hear itself).
  void nmt_start_all() {
    CanFrame f = {};
    f.id = 0x000;
    f.dlc = 2;
    f.data[0] = canopen::kNmtStart;
    ASSERT_TRUE(stations[0]->link.send(f));
    stations[0]->node().local_nmt(canopen::kNmtStart, bus.now);
  }

  /// Node k (k >= 2) consumes node k-1's TPDO1 with its RPDO1: inputs of one
  /// node become outputs of the next.
  void chain_pdos() {
    for (uint8_t k = 2; k <= count(); ++k) {
      canopen::ObjectDictionary& od = node(k).io.od();
      const uint32_t off = 0x80000000u | 0x200u | k;
      const uint32_t on = 0x180u + k - 1u;
      uint8_t b[4];
      canopen::put_le32(b, off);
      ASSERT_EQ(od.write(0x1400, 1, b, 4), canopen::kSdoOk);
      canopen::put_le32(b, on);
      ASSERT_EQ(od.write(0x1400, 1, b, 4), canopen::kSdoOk);
    }
  }

  /// The SYNC's line time at most (longest stuffing) and the poll cycle.
  uint32_t sync_us() const { return stations[0]->link.line_time_us(stations[0]->link.sync_frame_bytes()); }
  uint32_t cycle_bound_us() const { return count() * (config.window_us + sync_us()); }

  /// Every message on the line was sent by the node whose window it was and
  /// ended inside that window; SYNCs came from the poller (polling) or from
  /// the holder or the starter (token). Returns the messages checked.
  int check_windows(uint32_t from_us = 0) const {
    int checked = 0;
    const SerialBus::Sent* sync = nullptr;  // the last SYNC on the line
    for (const SerialBus::Sent& m : bus.log) {
      const bool is_sync = m.can_id == 0x080 && m.msg.length == 1;
      if (static_cast<int32_t>(m.start_us - from_us) >= 0) {
        EXPECT_FALSE(m.collided) << "talker " << m.talker << " at " << m.start_us;
        if (is_sync) {
          if (!token_) {
            EXPECT_EQ(m.talker, 0) << "only the poller SYNCs";
          } else if (sync != nullptr && m.talker != 0) {
            EXPECT_EQ(m.talker + 1, sync->msg.data[0])
                << "a token is passed by its holder, at " << m.start_us;
            EXPECT_LE(m.end_us - sync->end_us, config.window_us) << "the pass ends inside the window";
          }
        } else if (sync != nullptr) {
          EXPECT_EQ(m.talker + 1, sync->msg.data[0])
              << "node " << m.talker + 1 << " talked in the window of node " << int(sync->msg.data[0])
              << " at " << m.start_us;
          EXPECT_GE(static_cast<int32_t>(m.start_us - sync->end_us), 0);
          EXPECT_LE(m.end_us - sync->end_us, config.window_us - config.guard_us)
              << "node " << m.talker + 1 << " overran its window at " << m.start_us;
          ++checked;
        }
      }
      if (is_sync) sync = &m;
    }
    return checked;
  }

  /// Messages on the line from node `id` with CAN id `can_id`.
  std::vector<SerialBus::Sent> sent_by(uint8_t id, uint16_t can_id) const {
    std::vector<SerialBus::Sent> out;
    for (const SerialBus::Sent& m : bus.log) {
      if (m.talker + 1 == id && m.can_id == can_id) out.push_back(m);
    }
    return out;
  }

 private:
  bool token_ = false;
};

}  // namespace test
}  // namespace mb2co
