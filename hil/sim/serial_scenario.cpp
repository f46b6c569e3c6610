#include "sim/serial_scenario.h"

#include <memory>
#include <random>
#include <vector>

#include "canopen/nmt_slave.h"
#include "sim/serial_station.h"
#include "timing/serial_segment.h"

namespace mb2co {
namespace sim {
namespace {

using serialnet::Access;
using serialnet::BusConfig;

const uint16_t kSyncId = 0x080;

BusConfig bus_config(const SerialScenarioConfig& c) {
  BusConfig b = {};
  b.set = serialnet::connection_set(c.bits);
  b.baud = c.baud;
  b.access = c.token ? Access::kToken : Access::kPolled;
  b.first_node = 1;
  b.last_node = c.nodes;
  b.window_us = c.window_us;
  b.guard_us = c.guard_us;
  return b;
}

void put_le(uint8_t* b, uint32_t v, int n) {
  for (int i = 0; i < n; ++i) b[i] = static_cast<uint8_t>(v >> (8 * i));
}

// The segment with its nodes powered up, configured (1019h, heartbeat, node
// k's RPDO1 on node k-1's TPDO1) and started by node 1's NMT.
struct Segment {
  Segment(const SerialScenarioConfig& sc, const BusConfig& config) : bus(config.set, config.baud) {
    for (uint8_t i = 0; i < sc.nodes; ++i) {
      BusConfig c = config;
      if (i == 0) c.access = sc.token ? Access::kTokenStarter : Access::kPoller;
      stations.emplace_back(new SerialStation(bus, i, c, static_cast<uint8_t>(i + 1)));
      stations.back()->keep_received = false;
    }
    for (uint8_t id = 1; id <= sc.nodes; ++id) {
      SerialStation& s = node(id);
      s.node().start(id, bus.now);
      canopen::ObjectDictionary& od = s.io.od();
      uint8_t b[4];
      b[0] = sc.nodes;  // the SYNC counter runs 1..N: 1019h must allow it
      od.write(0x1019, 0, b, 1);
      put_le(b, sc.heartbeat_ms, 2);
      od.write(0x1017, 0, b, 2);
      if (id >= 2) {
        put_le(b, 0x80000000u | 0x200u | id, 4);
        od.write(0x1400, 1, b, 4);
        put_le(b, 0x180u + id - 1u, 4);
        od.write(0x1400, 1, b, 4);
      }
    }
    CanFrame f = {};
    f.id = 0x000;
    f.dlc = 2;
    f.data[0] = canopen::kNmtStart;
    node(1).link.send(f);
    node(1).node().local_nmt(canopen::kNmtStart, bus.now);
  }
  SerialStation& node(uint8_t id) { return *stations[id - 1u]; }

  SerialBus bus;
  std::vector<std::unique_ptr<SerialStation>> stations;
};

// Online measurement: every message as it is written, every frame as a
// node core queues it.
struct Meter {
  Meter(uint8_t nodes, SerialScenarioResult& r) : r_(r), pending_(nodes + 1u, kNone) {}

  void queued(uint8_t id, const CanFrame& f, uint32_t now_us) {
    if (measuring && f.id == 0x180u + id && pending_[id] == kNone) pending_[id] = now_us;
  }

  void sent(const SerialBus::Sent& s) {
    ++r_.messages;
    if (have_last_ && removed) {
      const uint32_t gap = s.end_us - last_end_us_;
      if (gap > r_.silence_max_us) r_.silence_max_us = gap;
    }
    have_last_ = true;
    last_end_us_ = s.end_us;
    const uint8_t id = static_cast<uint8_t>(s.talker + 1);
    if (s.can_id == kSyncId && s.msg.length == 1 && s.msg.data[0] == 1) cycle_start(s.end_us);
    if (!measuring) return;
    if (s.can_id == 0x080u + id || (s.can_id >= 0x580u && s.can_id < 0x680u)) ++r_.unexpected;
    if (s.can_id == 0x180u + id && pending_[id] != kNone) {
      const uint32_t latency = s.end_us - pending_[id];
      pending_[id] = kNone;
      const uint32_t bound = removed ? r_.pdo_bound_missing_us : r_.pdo_bound_us;
      ++r_.pdos;
      r_.pdo_sum_us += latency;
      if (latency > r_.pdo_max_us) r_.pdo_max_us = latency;
      if (latency > bound) ++r_.pdos_late;
    }
  }

  void cycle_start(uint32_t at_us) {
    if (measuring && have_cycle_) {
      const uint32_t cycle = at_us - cycle_start_us_;
      uint32_t& max = removed ? r_.cycle_max_missing_us : r_.cycle_max_us;
      if (cycle > max) max = cycle;
      r_.cycle_sum_us += cycle;
      ++r_.cycles;
    }
    have_cycle_ = measuring;
    cycle_start_us_ = at_us;
  }

  bool measuring = false;
  bool removed = false;

 private:
  static const uint32_t kNone = 0xFFFFFFFFu;
  SerialScenarioResult& r_;
  std::vector<uint32_t> pending_;  ///< queue time of node id's waiting TPDO1
  uint32_t last_end_us_ = 0;
  uint32_t cycle_start_us_ = 0;
  bool have_last_ = false;
  bool have_cycle_ = false;
};

}  // namespace

SerialScenarioResult serial_scenario(const SerialScenarioConfig& sc) {
  SerialScenarioResult r;
  const BusConfig config = bus_config(sc);
  r.cycle_bound_us = timing::access_cycle_us(config, 0);
  r.cycle_bound_missing_us = timing::access_cycle_us(config, sc.remove_node != 0 ? 1 : 0);
  r.recovery_bound_us = timing::token_recovery_us(config);
  // TPDO1 of the I/O node: 2 data bytes, nothing of higher priority queued
  // with it (no EMCY, no SDO: counted in `unexpected` if there were).
  r.pdo_bound_us = timing::serial_latency(config, 2, 2, nullptr, 0, 0).worst_us;
  r.pdo_bound_missing_us =
      timing::serial_latency(config, 2, 2, nullptr, 0, sc.remove_node != 0 ? 1 : 0).worst_us;

  Segment seg(sc, config);
  Meter meter(sc.nodes, r);
  seg.bus.on_sent = [&meter](const SerialBus::Sent& s) { meter.sent(s); };
  for (uint8_t id = 1; id <= sc.nodes; ++id) {
    seg.node(id).on_queued = [&meter, id](const CanFrame& f, uint32_t now_us) {
      meter.queued(id, f, now_us);
    };
  }
  seg.bus.run_for(2 * r.cycle_bound_us);  // boot-ups, NMT start
  meter.measuring = true;
  const uint32_t t0 = seg.bus.now;

  // About one input change per node per cycle, at random moments: paced by
  // the cycle measured so far (a token round is far shorter than its bound).
  std::mt19937 rng(sc.seed);
  std::vector<uint8_t> inputs(sc.nodes + 1u, 0);
  bool present = true;
  while (r.cycles < sc.cycles) {
    const uint64_t cycle_us = r.cycles == 0 ? r.cycle_bound_us : r.cycle_sum_us / r.cycles;
    const uint32_t mean_gap_us = static_cast<uint32_t>(cycle_us / sc.nodes) + 1u;
    seg.bus.run_for(1u + static_cast<uint32_t>(rng() % (2u * mean_gap_us)));
    const uint8_t id = static_cast<uint8_t>(1u + rng() % sc.nodes);
    if (sc.remove_node == id && !present) continue;
    seg.node(id).io.set_input(0, ++inputs[id]);
    if (present && sc.remove_node > 1 && r.cycles >= sc.cycles / 2) {
      // With token passing the node goes while it holds the token: the
      // token dies with it and only the starter's recovery brings it back.
      SerialStation& gone = seg.node(sc.remove_node);
      for (uint32_t i = 0; sc.token && i < r.cycle_bound_us && !gone.link.holds_token(); i += 10) {
        seg.bus.run_for(10);
      }
      r.removed_holding_token = gone.link.holds_token();
      seg.bus.detach(sc.remove_node - 1);
      present = false;
      meter.removed = true;
    }
  }
  seg.bus.run_for(2 * r.cycle_bound_missing_us);  // the last changes reach their consumers
  r.events_us = seg.bus.now - t0;
  r.collisions = seg.bus.collisions;
  r.recoveries = seg.node(1).link.counters().token_recoveries;
  for (uint8_t id = 1; id <= sc.nodes; ++id) {
    const serialnet::Decoder::Counters& d = seg.node(id).link.decoder_counters();
    if (id != sc.remove_node) r.decode_errors += uint32_t{d.bad_crc} + d.bad_length + d.bad_id + d.truncated;
    if (id >= 2 && id != sc.remove_node && id - 1 != sc.remove_node &&
        seg.node(id).io.output(0) != inputs[id - 1u]) {
      ++r.outputs_wrong;
    }
  }
  const bool recovery_ok =
      !sc.token || sc.remove_node == 0 || (r.recoveries > 0 && r.silence_max_us <= r.recovery_bound_us);
  r.ok = r.pdos > 0 && r.pdos_late == 0 && r.collisions == 0 && r.decode_errors == 0 && r.unexpected == 0 &&
         r.outputs_wrong == 0 && r.cycle_max_us <= r.cycle_bound_us &&
         r.cycle_max_missing_us <= r.cycle_bound_missing_us && recovery_ok;
  return r;
}

}  // namespace sim
}  // namespace mb2co
