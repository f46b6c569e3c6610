#include "sim/lab_bound.h"

#include "canopen/pdo_map.h"
#include "modbus/master_codec.h"
#include "sim/pc_programs.h"
#include "timing/line_config.h"
#include "timing/time_base.h"

namespace mb2co {
namespace sim {
namespace {

uint32_t ceil_us(SimNs ns) {
  return static_cast<uint32_t>((ns + kNsPerUs - 1) / kNsPerUs);
}

uint32_t od_get(canopen::ObjectDictionary& od, uint16_t index, uint8_t sub) {
  return od.get(od.find(index, sub));
}

/// The lab PC's two requests (for their processing cost on the Arduino).
SimNs lab_request_cost(const NodeTiming& t, bool remote) {
  uint8_t req[16];
  const uint16_t n = remote ? modbus::build_read_request(req, sizeof req, 1, modbus::fc::kReadInputRegisters,
                                                         regs::kIrRemoteButtons, 1)
                            : modbus::build_read_request(req, sizeof req, 1, modbus::fc::kReadDiscreteInputs,
                                                         regs::kDiStart, 1);
  const SimNs read = request_cost(t, req, n);
  const uint16_t w = modbus::build_write_single_coil(req, sizeof req, 1, regs::kCoilLabLed, true);
  const SimNs write = request_cost(t, req, w);
  return read > write ? read : write;
}

}  // namespace

SimNs firmware_step_ns(const NodeTiming& t, SimNs pass_max_ns) {
  const SimNs gap = t.loop_ns > pass_max_ns ? t.loop_ns : pass_max_ns;
  return gap + pass_max_ns;
}

uint32_t application_interarrival_us(const LineConfig& c, uint32_t entry) {
  const uint32_t debounce_us = uint32_t{c.debounce_ms} * 1000u;
  if ((entry >> 16) == 0x6000) return debounce_us;
  if ((entry >> 16) == 0x6200) {
    const uint32_t pc_min_us = static_cast<uint32_t>((c.pc.cycle_ns - c.pc.jitter_ns) / kNsPerUs);
    return pc_min_us < debounce_us ? pc_min_us : debounce_us;
  }
  return 0;
}

namespace {

/// The SYNC producer's period (1006h, µs) and COB-ID on `line`; false when
/// no station produces SYNC (1005h bit 30).
bool sync_producer(Line& line, uint32_t* period_us, uint32_t* cob_id) {
  for (int s = 0; s < line.size(); ++s) {
    canopen::ObjectDictionary& od = line.node(s).gateway().od();
    const uint32_t cob = od_get(od, 0x1005, 0);
    const uint32_t period = od_get(od, 0x1006, 0);
    if ((cob & 0x40000000u) && period != 0) {
      *period_us = period;
      *cob_id = cob & 0x7FFu;
      return true;
    }
  }
  return false;
}

}  // namespace

uint32_t tpdo_inhibit_us(Line& line, uint32_t cob_id) {
  for (int s = 0; s < line.size(); ++s) {
    canopen::ObjectDictionary& od = line.node(s).gateway().od();
    for (uint16_t n = 0; n < 4; ++n) {
      const uint32_t cob = od_get(od, static_cast<uint16_t>(0x1800 + n), 1);
      if (!(cob & 0x80000000u) && (cob & 0x7FFu) == cob_id)
        return od_get(od, static_cast<uint16_t>(0x1800 + n), 3) * 100u;
    }
  }
  return 0;
}

bool line_can_messages(Line& line, uint32_t jitter_us, std::vector<timing::MessageSpec>* out,
                       std::string* error) {
  const LineConfig& c = line.config();
  out->clear();
  uint32_t sync_period_us = 0;
  uint32_t sync_cob = 0;
  const bool sync = sync_producer(line, &sync_period_us, &sync_cob);
  for (int s = 0; s < line.size(); ++s) {
    // The OD as saved (a node powers on with it): read from a commissioned node.
    canopen::ObjectDictionary& od = line.node(s).gateway().od();
    for (uint16_t n = 0; n < 4; ++n) {
      const uint32_t cob = od_get(od, static_cast<uint16_t>(0x1800 + n), 1);
      const uint8_t count = static_cast<uint8_t>(od_get(od, static_cast<uint16_t>(0x1A00 + n), 0));
      if ((cob & 0x80000000u) || count == 0) continue;
      uint32_t bits = 0;
      for (uint8_t k = 1; k <= count; ++k)
        bits += canopen::map_bits(od_get(od, static_cast<uint16_t>(0x1A00 + n), k));
      const uint32_t type = od_get(od, static_cast<uint16_t>(0x1800 + n), 2);
      uint32_t t_us = 0;
      if (type <= 240) {  // synchronous: at most once per SYNC (every n-th for n > 0)
        if (!sync) continue;
        t_us = sync_period_us * (type == 0 ? 1u : type);
      } else {
        const uint32_t inhibit_us = od_get(od, static_cast<uint16_t>(0x1800 + n), 3) * 100u;
        const uint32_t first = od_get(od, static_cast<uint16_t>(0x1A00 + n), 1);
        t_us = inhibit_us != 0 ? inhibit_us : application_interarrival_us(c, first);
      }
      if (t_us == 0) {
        *error = strf("TPDO%u of node %d has neither an inhibit time nor a known event rate", n + 1, s + 1);
        return false;
      }
      timing::MessageSpec m{};
      timing::set_name(m, strf("TPDO%u.%d", n + 1, s + 1).c_str());
      m.id = cob & 0x7FFu;
      m.dlc = static_cast<uint8_t>((bits + 7) / 8);
      m.period_us = m.deadline_us = t_us;
      m.jitter_us = jitter_us;
      out->push_back(m);
    }
    const uint32_t hb_ms = od_get(od, 0x1017, 0);
    if (hb_ms != 0) {
      timing::MessageSpec m{};
      timing::set_name(m, strf("HB.%d", s + 1).c_str());
      m.id = 0x700u + static_cast<uint32_t>(s + 1);
      m.dlc = 1;
      m.period_us = m.deadline_us = hb_ms * 1000u;
      m.jitter_us = jitter_us;
      out->push_back(m);
    }
  }
  if (sync) {
    timing::MessageSpec m{};
    timing::set_name(m, "SYNC");
    m.id = sync_cob;
    m.dlc = 0;
    m.period_us = m.deadline_us = sync_period_us;
    m.jitter_us = jitter_us;
    out->push_back(m);
  }
  timing::sort_by_priority(out->data(), out->size());
  return true;
}

bool hop_times(const std::vector<timing::MessageSpec>& messages, uint32_t id, uint32_t bitrate_bps,
               HopTimes* out) {
  std::vector<timing::MessageSpec> set = messages;
  size_t at = set.size();
  for (size_t i = 0; i < set.size(); ++i) {
    if (set[i].id == id) at = i;
  }
  if (at == set.size()) return false;
  set[at].jitter_us = 0;
  std::vector<timing::RtaMessage> rta(set.size());
  std::vector<timing::RtaResult> res(set.size());
  size_t bad = 0;
  if (timing::analyse_set(set.data(), set.size(), bitrate_bps, timing::WorstCase::kDavis, rta.data(),
                          res.data(), &bad) != timing::RtaStatus::kOk ||
      res[at].revised != timing::Bound::kBounded) {
    return false;
  }
  out->best_ns = timing::can_hop_best_ns(false, set[at].dlc, bitrate_bps);
  out->worst_ns = timing::ticks_to_ns_ceil(res[at].r, bitrate_bps);
  out->frame_worst_ns = timing::ticks_to_ns_ceil(rta[at].c, bitrate_bps);
  return true;
}

namespace {

/// The lab's bound with passes that hand in at most `bytes` characters and
/// answer a request costing `request` (the PC's; 0 with no PC in the loop).
LabBound bound_with(Line& line, bool remote, size_t bytes, SimNs request) {
  LabBound out;
  const LineConfig& c = line.config();
  if (c.lab_pc < 0) {
    out.error = "the line has no lab stations";
    return out;
  }
  const NodeTiming& nt = c.node;
  out.pass_max_ns = max_pass_ns(nt, nt.can_rx_buffers, bytes, request);
  out.step_ns = firmware_step_ns(nt, out.pass_max_ns);

  timing::LatencyParams& p = out.params;
  p.debounce_us = uint32_t{c.debounce_ms} * 1000u;
  p.fw_loop_us = ceil_us(out.step_ns);
  p.pc_cycle_us = ceil_us(c.pc.cycle_ns + c.pc.jitter_ns);
  p.pc_compute_us = ceil_us(c.pc.compute_ns);
  p.master_end_us = 0;  // the PC predicts the response length
  p.serial.baud = c.baud;
  p.serial.parity = timing::Parity::kEven;
  p.slave_waits_t35 = true;
  p.read = remote ? timing::read_registers_exchange(1) : timing::read_bits_exchange(1);
  p.write = timing::write_single_exchange();
  p.inhibit_us = 0;

  if (!remote) {
    out.bound = timing::modbus_only_latency(p);
    out.ok = true;
    return out;
  }

  const uint32_t bitrate = c.bitrate_kbit * 1000u;
  const uint32_t up_id = 0x280u + static_cast<uint32_t>(c.lab_remote + 1);
  const uint32_t down_id = 0x380u + static_cast<uint32_t>(c.lab_pc + 1);
  if (!line_can_messages(line, p.fw_loop_us, &out.messages, &out.error)) return out;
  const uint32_t up_inhibit_us = tpdo_inhibit_us(line, up_id);
  const uint32_t down_inhibit_us = tpdo_inhibit_us(line, down_id);
  p.inhibit_us = up_inhibit_us > down_inhibit_us ? up_inhibit_us : down_inhibit_us;
  HopTimes up, down;
  if (!hop_times(out.messages, up_id, bitrate, &up) || !hop_times(out.messages, down_id, bitrate, &down)) {
    out.error = strf("no bounded CAN response time for the lab PDOs at %u kbit/s", c.bitrate_kbit);
    return out;
  }
  p.can_up_best_ns = up.best_ns;
  p.can_up_worst_ns = up.worst_ns;
  p.can_down_best_ns = down.best_ns;
  p.can_down_worst_ns = down.worst_ns;
  out.bound = timing::modbus_canopen_latency(p);
  out.ok = true;
  return out;
}

}  // namespace

LabBound lab_bound(Line& line, bool remote) {
  return bound_with(line, remote, 8, lab_request_cost(line.config().node, remote));
}

LabBound arduino_control_bound(Line& line) {
  LabBound out = bound_with(line, true, 0, 0);
  if (out.ok) out.bound = timing::arduino_control_latency(out.params);
  return out;
}

}  // namespace sim
}  // namespace mb2co
