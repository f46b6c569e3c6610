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

LabBound lab_bound(Line& line, bool remote) {
  LabBound out;
  const LineConfig& c = line.config();
  if (c.lab_pc < 0) {
    out.error = "the line has no lab stations";
    return out;
  }
  const NodeTiming& nt = c.node;
  out.pass_max_ns = max_pass_ns(nt, nt.can_rx_buffers, 8, lab_request_cost(nt, remote));
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

  // The line's CAN traffic, from what each Arduino was commissioned with.
  const uint32_t jitter_us = p.fw_loop_us;
  const uint32_t bitrate = c.bitrate_kbit * 1000u;
  const uint32_t up_id = 0x280u + static_cast<uint32_t>(c.lab_remote + 1);
  const uint32_t down_id = 0x380u + static_cast<uint32_t>(c.lab_pc + 1);
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
      const uint32_t inhibit_us = od_get(od, static_cast<uint16_t>(0x1800 + n), 3) * 100u;
      const uint32_t first = od_get(od, static_cast<uint16_t>(0x1A00 + n), 1);
      const uint32_t t_us = inhibit_us != 0 ? inhibit_us : application_interarrival_us(c, first);
      if (t_us == 0) {
        out.error =
            strf("TPDO%u of node %d has neither an inhibit time nor a known event rate", n + 1, s + 1);
        return out;
      }
      timing::MessageSpec m{};
      timing::set_name(m, strf("TPDO%u.%d", n + 1, s + 1).c_str());
      m.id = cob & 0x7FFu;
      m.dlc = static_cast<uint8_t>((bits + 7) / 8);
      m.period_us = m.deadline_us = t_us;
      m.jitter_us = jitter_us;
      out.messages.push_back(m);
      if (m.id == up_id || m.id == down_id) {
        const uint32_t hop_inhibit = inhibit_us;
        if (hop_inhibit > p.inhibit_us) p.inhibit_us = hop_inhibit;
      }
    }
    const uint32_t hb_ms = od_get(od, 0x1017, 0);
    if (hb_ms != 0) {
      timing::MessageSpec m{};
      timing::set_name(m, strf("HB.%d", s + 1).c_str());
      m.id = 0x700u + static_cast<uint32_t>(s + 1);
      m.dlc = 1;
      m.period_us = m.deadline_us = hb_ms * 1000u;
      m.jitter_us = jitter_us;
      out.messages.push_back(m);
    }
  }
  timing::sort_by_priority(out.messages.data(), out.messages.size());

  // Each hop is analysed with its own jitter 0: the wait for the pass that
  // queues it is already the loop term before it.
  auto hop = [&](uint32_t id, uint64_t* best_ns, uint64_t* worst_ns) {
    std::vector<timing::MessageSpec> set = out.messages;
    size_t at = set.size();
    for (size_t i = 0; i < set.size(); ++i) {
      if (set[i].id == id) at = i;
    }
    if (at == set.size()) return false;
    set[at].jitter_us = 0;
    std::vector<timing::RtaMessage> rta(set.size());
    std::vector<timing::RtaResult> res(set.size());
    size_t bad = 0;
    if (timing::analyse_set(set.data(), set.size(), bitrate, timing::WorstCase::kDavis, rta.data(),
                            res.data(), &bad) != timing::RtaStatus::kOk ||
        res[at].revised != timing::Bound::kBounded) {
      return false;
    }
    *best_ns = timing::can_hop_best_ns(false, set[at].dlc, bitrate);
    *worst_ns = timing::ticks_to_ns_ceil(res[at].r, bitrate);
    return true;
  };
  if (!hop(up_id, &p.can_up_best_ns, &p.can_up_worst_ns) ||
      !hop(down_id, &p.can_down_best_ns, &p.can_down_worst_ns)) {
    out.error = strf("no bounded CAN response time for the lab PDOs at %u kbit/s", c.bitrate_kbit);
    return out;
  }
  out.bound = timing::modbus_canopen_latency(p);
  out.ok = true;
  return out;
}

}  // namespace sim
}  // namespace mb2co
