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
/// the token starter (token passing), and has the SDO client. `node_windows`
/// (optional, outliving the segment): node n's own window at [n - 1].
class Segment {
 public:
  Segment(serialnet::IdBits bits, uint8_t nodes, bool token, uint32_t window_us = 3600,
          const uint32_t* node_windows = nullptr, uint32_t guard_us = 100, uint32_t baud = 115200)
      : bus(serialnet::connection_set(bits), baud) {
    config.set = serialnet::connection_set(bits);
    config.baud = baud;
    config.first_node = 1;
    config.last_node = nodes;
    config.window_us = window_us;
    config.guard_us = guard_us;
    config.max_gap_us = 0;
    config.node_windows_us = node_windows;
    for (uint8_t i = 0; i < nodes; ++i) {
      serialnet::BusConfig c = config;
      if (token) {
        c.access = i == 0 ? serialnet::Access::kTokenStarter : serialnet::Access::kToken;
      } else {
        c.access = i == 0 ? serialnet::Access::kPoller : serialnet::Access::kPolled;
      }
      EXPECT_EQ(serialnet::check_config(c), serialnet::ConfigError::kOk);
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

  /// start(), optionally chain_pdos(), nmt_start_all(), then `settle_us` of
  /// running: every test's way to an operational segment.
  void bring_up(uint16_t heartbeat_ms, bool chain, uint32_t settle_us) {
    start(heartbeat_ms);
    if (chain) chain_pdos();
    nmt_start_all();
    bus.run_for(settle_us);
  }

  /// Station 1's SDO client reads (index, sub) of node `id` into buf; runs
  /// the line until the transfer ends. Returns the bytes read (-1: failed).
  int upload(uint8_t id, uint16_t index, uint8_t sub, uint8_t* buf, uint32_t capacity) {
    Station& master = *stations[0];
    master.client_on = true;
    master.client.init(id);
    if (!master.client.start_upload(index, sub, canopen::kSdoAuto, buf, capacity, bus.now,
                                    master.link.can_sink())) {
      return -1;
    }
    for (int i = 0; i < 2000 && master.client.busy(); ++i) bus.run_for(1000);
    if (master.client.status() != canopen::SdoClient::kDone) return -1;
    return static_cast<int>(master.client.transferred());
  }

  /// Runs in 10 µs steps until node `id` holds the token (at most `limit_us`).
  bool run_until_token_at(uint8_t id, uint32_t limit_us = 1000000) {
    for (uint32_t t = 0; t < limit_us && !node(id).link.holds_token(); t += 10) bus.run_for(10);
    return node(id).link.holds_token();
  }

  /// The SYNC's line time at most (longest stuffing) and the poll cycle.
  uint32_t sync_us() const { return stations[0]->link.line_time_us(stations[0]->link.sync_frame_bytes()); }
  uint32_t cycle_bound_us() const {
    uint32_t sum = 0;
    for (uint8_t id = 1; id <= count(); ++id) sum += serialnet::window_of(config, id) + sync_us();
    return sum;
  }

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
            EXPECT_LE(m.end_us - sync->end_us, serialnet::window_of(config, sync->msg.data[0]))
                << "the pass ends inside the window";
          }
        } else if (sync != nullptr) {
          EXPECT_EQ(m.talker + 1, sync->msg.data[0])
              << "node " << m.talker + 1 << " talked in the window of node " << int(sync->msg.data[0])
              << " at " << m.start_us;
          EXPECT_GE(static_cast<int32_t>(m.start_us - sync->end_us), 0);
          EXPECT_LE(m.end_us - sync->end_us,
                    serialnet::window_of(config, sync->msg.data[0]) - config.guard_us)
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

/// Polling or token passing in each of the four connection sets: a PDO from
/// node 1 reaches node 2, every node beats, nobody talks out of turn.
inline void check_every_connection_set(bool token) {
  for (serialnet::IdBits bits :
       {serialnet::IdBits::k8, serialnet::IdBits::k7, serialnet::IdBits::k6, serialnet::IdBits::k11}) {
    const uint8_t nodes = bits == serialnet::IdBits::k6 ? 7 : 5;
    Segment seg(bits, nodes, token);
    seg.bring_up(100, true, 300000);
    seg.node(1).io.set_input(0, 0x33);
    seg.bus.run_for(100000);
    EXPECT_EQ(seg.node(2).io.output(0), 0x33) << int(bits);
    for (uint8_t id = 1; id <= nodes; ++id) {
      EXPECT_GE(seg.sent_by(id, static_cast<uint16_t>(0x700u + id)).size(), 3u)
          << int(bits) << ":" << int(id);
    }
    EXPECT_GT(seg.check_windows(), 3 * nodes);
    EXPECT_EQ(seg.bus.collisions, 0);
  }
}

}  // namespace test
}  // namespace mb2co
