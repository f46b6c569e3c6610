#include "sim/lab_bound.h"

#include <algorithm>

#include "canopen/pdo_map.h"
#include "modbus/master_codec.h"
#include "sim/lab_hops.h"
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

/// Processing cost on the Arduino of the lab PC's read (FC 02 of the START
/// input, or FC 04 of the remote buttons' register on the CANopen path).
SimNs lab_read_cost(const NodeTiming& t, bool remote) {
  uint8_t req[16];
  const uint16_t n = remote ? modbus::build_read_request(req, sizeof req, 1, modbus::fc::kReadInputRegisters,
                                                         pc_registers().remote_buttons, 1)
                            : modbus::build_read_request(req, sizeof req, 1, modbus::fc::kReadDiscreteInputs,
                                                         pc_registers().start, 1);
  return request_cost(t, req, n);
}

/// The same for its write of the lab LED (FC 05).
SimNs lab_write_cost(const NodeTiming& t) {
  uint8_t req[16];
  const uint16_t n = modbus::build_write_single_coil(req, sizeof req, 1, pc_registers().lab_led, true);
  return request_cost(t, req, n);
}

/// The dearer of the lab PC's two requests.
SimNs lab_request_cost(const NodeTiming& t, bool remote) {
  return std::max(lab_read_cost(t, remote), lab_write_cost(t));
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

Status line_can_messages(Line& line, uint32_t jitter_us, std::vector<timing::MessageSpec>* out) {
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
        return Status::failure(
            strf("TPDO%u of node %d has neither an inhibit time nor a known event rate", n + 1, s + 1));
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
  return Status::ok();
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
  p.serial.parity = modbus::Parity::kEven;
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
  const Status listed = line_can_messages(line, p.fw_loop_us, &out.messages);
  if (!listed) {
    out.error = listed.message();
    return out;
  }
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

/// Response time (ns) of every message of `set` at `bitrate_bps` (the
/// longest in `longest`); false when one is unbounded.
bool response_times(const std::vector<timing::MessageSpec>& set, uint32_t bitrate_bps,
                    std::vector<MessageLateness>* out, SimNs* longest) {
  out->clear();
  *longest = 0;
  if (set.empty()) return true;
  std::vector<timing::RtaMessage> rta(set.size());
  std::vector<timing::RtaResult> res(set.size());
  size_t bad = 0;
  if (timing::analyse_set(set.data(), set.size(), bitrate_bps, timing::WorstCase::kDavis, rta.data(),
                          res.data(), &bad) != timing::RtaStatus::kOk) {
    return false;
  }
  for (size_t i = 0; i < set.size(); ++i) {
    if (res[i].revised != timing::Bound::kBounded) return false;
    const SimNs r = timing::ticks_to_ns_ceil(res[i].r, bitrate_bps);
    out->push_back(MessageLateness{set[i].id, r});
    *longest = std::max(*longest, r);
  }
  return true;
}

/// True when station `s` maps `cob_id` by an event-driven RPDO (types
/// 241..255 apply the data as the frame is taken in, CiA 301; 0..240 wait
/// for the next SYNC) and by no synchronous one.
bool rpdo_applied_at_reception(Line& line, int s, uint32_t cob_id) {
  canopen::ObjectDictionary& od = line.node(s).gateway().od();
  bool found = false;
  for (uint16_t n = 0; n < 4; ++n) {
    const uint32_t cob = od_get(od, static_cast<uint16_t>(0x1400 + n), 1);
    if ((cob & 0x80000000u) || (cob & 0x7FFu) != cob_id) continue;
    if (od_get(od, static_cast<uint16_t>(0x1400 + n), 2) <= 240) return false;
    found = true;
  }
  return found;
}

/// micros() resolution: a comparison of two µs stamps (debounce, t3.5,
/// inhibit time) may pass up to 1 µs after the real time.
constexpr SimNs kClockNs = kNsPerUs;

/// The bound per kind of pass (docs/timing.md §9). Passes are counted
/// without the CAN frames they take in: those are a term of their own, the
/// frames each Arduino's passes on the path can take in (at most
/// can_rx_buffers per pass; "Frames on the path").
class TightBound {
 public:
  TightBound(const LineConfig& c, bool remote, LabBound& out) : c_(c), t_(c.node), out_(out) {
    plain_ = t_.pass_ns + t_.jitter_ns;
    chars_ = 8 * t_.byte_ns;  // one request: the PC sends the next ≥ t3.5 + a pass after
    read_ = lab_read_cost(t_, remote);
    write_ = lab_write_cost(t_);
    frames_per_pass_ = t_.frame_ns * t_.can_rx_buffers;
    t35_ = timing::t35_ns(out.params.serial);
    // The pass before the one that answers a request started after the
    // request's last character when no pass without a request is longer
    // than t3.5: the answering pass then takes no character.
    const SimNs handling_chars = wait(plain_ + chars_ + frames_per_pass_) <= t35_ ? 0 : chars_;
    out_.plain_pass_ns = plain_;
    out_.read_pass_ns = plain_ + handling_chars + read_;
    out_.write_pass_ns = plain_ + handling_chars + write_;
    // Strictly periodic passes (every pass shorter than the loop period)
    // start a whole number of periods after the one that first saw the
    // press: the debounce then ends at a pass start.
    const SimNs any = plain_ + chars_ + std::max(read_, write_) + frames_per_pass_;
    debounce_ns_ = SimNs{c_.debounce_ms} * kNsPerMs;
    grid_ = t_.loop_ns != 0 && any <= t_.loop_ns;
    periodic_ = grid_ && debounce_ns_ % t_.loop_ns == 0;
    longest_wait_ = wait(any);
  }

  /// Builds the terms with `frames_pc` / `frames_led` frames; false when
  /// they do not fit a LatencyBound.
  bool build(bool remote, const HopTimes& up, const HopTimes& down, uint32_t up_inhibit_us,
             uint32_t down_inhibit_us, uint32_t frames_pc, uint32_t frames_led) {
    b_ = timing::LatencyBound{};
    const timing::LatencyParams& p = out_.params;
    const timing::PollCycle cycle = timing::poll_cycle(p);
    const SimNs split = c_.pc.split_ppm != 0 ? c_.pc.split_gap_max_ns : 0;
    const SimNs seen = wait(plain_ + chars_);  // the PC's Arduino, no request in progress (§9)
    const SimNs read_pass = out_.read_pass_ns;
    const SimNs write_pass = out_.write_pass_ns;
    const SimNs resp_best = timing::serial_frame_ns_floor(p.serial, p.read.response_bytes);
    const SimNs wreq_best = timing::serial_frame_ns_floor(p.serial, p.write.request_bytes);
    const SimNs compute = SimNs{p.pc_compute_us} * kNsPerUs;
    const SimNs master_end = SimNs{p.master_end_us} * kNsPerUs;
    // The PC's cycle, request end to request end: its period and start
    // jitter, or its read-write exchange when that is longer.
    const SimNs busy = cycle.read.request_ns + split + t35_ + kClockNs + seen + read_pass +
                       cycle.read.response_ns + master_end + compute + cycle.write.request_ns + split + t35_ +
                       kClockNs + seen + write_pass + cycle.write.response_ns + master_end +
                       4 * frames_per_pass_;
    const SimNs poll = std::max<SimNs>(c_.pc.cycle_ns + c_.pc.jitter_ns + split, busy);

    if (!remote) {
      const SimNs debounce_seen = periodic_ ? kClockNs : seen + kClockNs;
      add("press_seen", 0, press_seen(poll, seen, debounce_seen, split));
      add("debounce", debounce_ns_, debounce_ns_);
      add("debounce_seen", 0, debounce_seen);
    } else {
      const SimNs seen_led = wait(plain_);  // the LED's Arduino: no Modbus traffic
      add("press_seen", 0, seen_led);
      add("debounce", debounce_ns_, debounce_ns_);
      add("debounce_seen", 0, periodic_ ? kClockNs : seen_led + kClockNs);
      add("tpdo_pass", 0, plain_);
      // A held-back PDO goes out in the first pass after its inhibit time.
      if (up_inhibit_us != 0)
        add("inhibit_up", 0, SimNs{up_inhibit_us} * kNsPerUs + kClockNs + seen_led + plain_);
      add("can_up", up.best_ns, up.worst_ns);
      // With an RPDO applied at reception the read that samples it starts
      // at most poll_wait after the frame arrived, whatever pass was in
      // progress (docs/timing.md §9, "The PDO's handover").
      if (!rpdo_at_reception_) add("rpdo_seen", 0, seen);
    }
    add("poll_wait", 0, poll + seen + kClockNs);
    add("read_pass", 0, read_pass);
    add("read_response", resp_best, cycle.read.response_ns);
    if (master_end != 0) add("master_end", master_end, master_end);
    if (compute != 0) add("pc_compute", compute, compute);
    add("write_request", wreq_best, cycle.write.request_ns + split);
    add("slave_end", t35_, t35_);
    add("write_seen", 0, write_seen(read_pass, master_end + compute + split, seen));
    add("write_pass", 0, write_pass);
    // The terms above that are passes of the PC's Arduino.
    uint32_t passes_pc = remote ? (rpdo_at_reception_ ? 4 : 5) : 6;
    uint32_t passes_led = 5;
    if (remote) {
      if (down_inhibit_us != 0) {
        add("inhibit_down", 0, SimNs{down_inhibit_us} * kNsPerUs + kClockNs + longest_wait_ + longest_wait_);
        passes_pc += 2;
      }
      if (up_inhibit_us != 0) passes_led += 2;
    }
    const uint64_t pc = std::min<uint64_t>(frames_pc, uint64_t{passes_pc} * t_.can_rx_buffers);
    const uint64_t led =
        remote ? std::min<uint64_t>(frames_led, uint64_t{passes_led} * t_.can_rx_buffers) : 0;
    if (remote) {
      add("can_down", down.best_ns, down.worst_ns);
      // The pass in progress, the one that sets the LED.
      add("led_pass", 0, led_seen((pc + led) * t_.frame_ns) + plain_);
    }
    out_.frames_pc = static_cast<uint32_t>(pc);
    out_.frames_led = static_cast<uint32_t>(led);
    add("frames", 0, (pc + led) * t_.frame_ns);
    return !full_;
  }

  /// The path's passes on the PC's Arduino (`pc`) or on the button's and
  /// LED's (Modbus + CANopen), grouped into runs of passes that follow one
  /// another, each with the interval its frames arrived in (docs/timing.md
  /// §9, "Frames on the path"). The same passes as build() counts; after
  /// build(), whose terms bound the intervals.
  std::vector<PathCluster> clusters(bool remote, bool pc, uint32_t up_inhibit_us,
                                    uint32_t down_inhibit_us) const {
    const SimNs w = longest_wait_;  // pass start to pass start, frames included
    std::vector<PathCluster> out;
    if (pc) {
      if (!remote) {
        out.push_back(PathCluster{1, w});  // press_seen
        out.push_back(PathCluster{1, w});  // debounce_seen
      } else if (!rpdo_at_reception_) {
        out.push_back(PathCluster{1, w});  // rpdo_seen
      }
      // The pass in progress when the read's t3.5 ends, the read pass,
      // write_seen's and the write pass: from the start of the pass before
      // the first to the start of the last.
      SimNs exchange = 0;
      for (const char* name : {"read_response", "master_end", "pc_compute", "write_request", "slave_end"})
        exchange += term_ns(name);
      out.push_back(PathCluster{4, 4 * w + out_.read_pass_ns + frames_per_pass_ + exchange + kClockNs});
      if (remote && down_inhibit_us != 0) out.push_back(PathCluster{2, 2 * w});  // inhibit_down
      return out;
    }
    out.push_back(PathCluster{1, w});                              // press_seen
    out.push_back(PathCluster{2, 2 * w});                          // debounce_seen, tpdo_pass
    if (up_inhibit_us != 0) out.push_back(PathCluster{2, 2 * w});  // inhibit_up
    out.push_back(PathCluster{2, 2 * w});                          // led_pass
    return out;
  }

  /// The PC's Arduino applies the button PDO when it receives it (an
  /// event-driven RPDO), before the pass answers a request.
  void set_rpdo_at_reception(bool yes) { rpdo_at_reception_ = yes; }

  const timing::LatencyBound& bound() const { return b_; }
  /// Longest pass start to pass start on the PC's Arduino, frames included.
  SimNs longest_wait() const { return longest_wait_; }

 private:
  SimNs wait(SimNs pass) const { return std::max(t_.loop_ns, pass); }

  /// The pass in progress when the write's t3.5 ends. With strictly
  /// periodic passes the read pass and the write pass both start on the
  /// loop's grid, so the write pass starts a whole number of periods after
  /// the read pass: the rest of the pass in progress is what is left to the
  /// next grid point after read pass + exchange (`pc_ns`: the PC's own part
  /// and the request's gap) + t3.5 (docs/timing.md §9, "On the loop's grid").
  SimNs write_seen(SimNs read_pass, SimNs pc_ns, SimNs seen) const {
    const SimNs any_pass = seen + kClockNs;
    if (!grid_) return any_pass;
    const timing::PollCycle cycle = timing::poll_cycle(out_.params);
    const SimNs to_t35 =
        read_pass + cycle.read.response_ns + pc_ns + cycle.write.request_ns + t35_ + kClockNs;
    // The read pass may be longer by the frames it took in.
    const SimNs longest = to_t35 + frames_per_pass_;
    const SimNs next = (longest + t_.loop_ns - 1) / t_.loop_ns * t_.loop_ns;
    return std::min(any_pass, next - to_t35);
  }

  /// The pass in progress at the LED's Arduino when the LED's PDO arrives
  /// (Modbus + CANopen), after can_down; `frames_ns`: the frames term. With
  /// strictly periodic passes and a debounce of whole periods the pass that
  /// counts the press and the one that sets the LED both start on that
  /// Arduino's grid, a whole number of periods apart: the wait is what is
  /// left to the next grid point after the terms between them
  /// (docs/timing.md §9, "On the loop's grid").
  SimNs led_seen(SimNs frames_ns) const {
    const SimNs any_pass = wait(plain_);
    if (!periodic_) return any_pass;
    SimNs chain = frames_ns;  // the frames may lengthen any pass between them
    bool in = false;
    for (size_t i = 0; i < b_.count; ++i) {
      if (std::string(b_.terms[i].name) == "tpdo_pass") in = true;
      if (in) chain += b_.terms[i].worst_ns;
    }
    const SimNs next = (chain + t_.loop_ns - 1) / t_.loop_ns * t_.loop_ns;
    return std::min(any_pass, next - chain + frames_ns);
  }

  /// Worst case of the term `name` of the last build(); 0 when absent.
  SimNs term_ns(const char* name) const {
    for (size_t i = 0; i < b_.count; ++i) {
      if (std::string(b_.terms[i].name) == name) return b_.terms[i].worst_ns;
    }
    return 0;
  }

  void add(const char* name, uint64_t best, uint64_t worst) {
    if (b_.count == timing::kMaxLatencyTerms) full_ = true;
    timing::add_latency_term(b_, name, best, worst);
  }

  /// The pass in progress when the button is pressed (Modbus only, where
  /// the PC's Arduino has the button). A read pass or one without a
  /// request: its own length (a pass answering a request takes no
  /// characters where no pass without one is longer than t3.5, the
  /// read_pass_ns / write_pass_ns of the constructor). A write pass of cycle k: the next read ends
  /// at most two poll periods after cycle k's read ended, which was ρ
  /// before that write pass began, whenever cycle k+2's read cannot end
  /// before the press is debounced (docs/timing.md §9).
  SimNs press_seen(SimNs poll, SimNs seen, SimNs debounce_seen, SimNs split) const {
    const timing::LatencyParams& p = out_.params;
    const SimNs read_or_plain = wait(std::max(out_.read_pass_ns, plain_ + chars_));
    const SimNs rho = t_.pass_ns + read_ + timing::serial_frame_ns_floor(p.serial, p.read.response_bytes) +
                      SimNs{p.master_end_us + p.pc_compute_us} * kNsPerUs +
                      timing::serial_frame_ns_floor(p.serial, p.write.request_bytes) + t35_;
    const timing::PollCycle cycle = timing::poll_cycle(p);
    const SimNs sigma = seen + kClockNs + out_.read_pass_ns + cycle.read.response_ns +
                        SimNs{p.master_end_us + p.pc_compute_us} * kNsPerUs + cycle.write.request_ns + split +
                        t35_ + kClockNs + seen + 3 * frames_per_pass_;
    const SimNs min_cycle = c_.pc.cycle_ns - c_.pc.jitter_ns - split;
    const bool two_cycles = 2 * min_cycle >= sigma + out_.write_pass_ns + frames_per_pass_ + debounce_ns_ +
                                                 debounce_seen + kClockNs;
    if (!two_cycles) return wait(std::max({out_.read_pass_ns, out_.write_pass_ns, plain_ + chars_}));
    // Press to the read that samples it: 2·poll + seen − ρ against the
    // terms press_seen + debounce + debounce_seen + poll_wait.
    const SimNs write_case = 2 * poll + seen + kClockNs;
    const SimNs others = rho + debounce_ns_ + debounce_seen + poll + seen + kClockNs;
    return std::max(read_or_plain, write_case > others ? write_case - others : 0);
  }

  const LineConfig& c_;
  const NodeTiming& t_;
  LabBound& out_;
  timing::LatencyBound b_ = {};
  bool full_ = false;
  SimNs plain_ = 0, chars_ = 0, read_ = 0, write_ = 0, frames_per_pass_ = 0, t35_ = 0;
  SimNs debounce_ns_ = 0, longest_wait_ = 0;
  bool grid_ = false;  ///< every pass starts a whole number of loop periods after the one before
  bool periodic_ = false;
  bool rpdo_at_reception_ = false;
};

}  // namespace

LabBound lab_bound(Line& line, bool remote, const LabOperator& op) {
  const LineConfig& c = line.config();
  LabBound out = bound_with(line, remote, 8, lab_request_cost(c.node, remote));
  if (!out.ok) return out;
  out.ok = false;
  const uint32_t bitrate = c.bitrate_kbit * 1000u;
  const uint32_t up_id = 0x280u + static_cast<uint32_t>(c.lab_remote + 1);
  const uint32_t down_id = 0x380u + static_cast<uint32_t>(c.lab_pc + 1);
  if (out.messages.empty()) {
    const Status listed = line_can_messages(line, out.params.fw_loop_us, &out.messages);
    if (!listed) {
      out.error = listed.message();
      return out;
    }
  }
  HopTimes up, down;
  SimNs longest_r = 0;
  if (remote &&
      (!hop_times(out.messages, up_id, bitrate, &up) || !hop_times(out.messages, down_id, bitrate, &down))) {
    out.error = strf("no bounded CAN response time for the lab PDOs at %u kbit/s", c.bitrate_kbit);
    return out;
  }
  std::vector<MessageLateness> late;
  if (!response_times(out.messages, bitrate, &late, &longest_r)) {
    out.error = strf("a message of the line has no bounded response time at %u kbit/s", c.bitrate_kbit);
    return out;
  }
  const uint32_t up_inhibit_us = remote ? tpdo_inhibit_us(line, up_id) : 0;
  const uint32_t down_inhibit_us = remote ? tpdo_inhibit_us(line, down_id) : 0;
  TightBound tight(c, remote, out);
  tight.set_rpdo_at_reception(remote && rpdo_applied_at_reception(line, c.lab_pc, up_id));
  // First with a full receive buffer in every pass of the path (sound on
  // its own), then with the frames the path's passes can take in during
  // that window: the press's window reaches back over the pass in progress
  // and the one before it, whose frames that pass took in.
  const uint32_t cap = ~uint32_t{0};
  if (!tight.build(remote, up, down, up_inhibit_us, down_inhibit_us, cap, cap)) {
    out.error = "too many terms";
    return out;
  }
  out.window_ns = tight.bound().worst_ns + 2 * tight.longest_wait();
  const SimNs jitter = out.step_ns + longest_r;              // a send's lateness and its time on the bus
  for (MessageLateness& l : late) l.late_ns += out.step_ns;  // the same, message by message
  const int button = remote ? c.lab_remote : c.lab_pc;
  uint32_t frames_pc = 0, frames_led = 0;
  Status counted = frames_on_path(line, c.lab_pc, button, out.window_ns, jitter, late, op,
                                  tight.clusters(remote, true, up_inhibit_us, down_inhibit_us), &frames_pc);
  if (counted && remote) {
    counted = frames_on_path(line, c.lab_remote, button, out.window_ns, jitter, late, op,
                             tight.clusters(remote, false, up_inhibit_us, down_inhibit_us), &frames_led);
  }
  if (!counted) {
    out.error = counted.message();
    return out;
  }
  tight.build(remote, up, down, up_inhibit_us, down_inhibit_us, frames_pc, frames_led);
  out.bound = tight.bound();
  out.ok = true;
  if (!remote) return out;
  // The two hops together (docs/timing.md §9): each line-state TPDO at one
  // hop, unless the hops are close, where the path between them is short.
  const JointHops joint =
      joint_hops(line, out.messages, up_id, down_id, bitrate, out.window_ns + jitter, out.step_ns);
  if (!joint.split) return out;
  uint64_t between = 0;  // the terms from the up hop's reception to the down PDO's queueing
  bool in = false;
  for (size_t i = 0; i < out.bound.count; ++i) {
    const std::string name = out.bound.terms[i].name;
    if (name == "can_down") in = false;
    if (in) between += out.bound.terms[i].worst_ns;
    if (name == "can_up") in = true;
  }
  const uint64_t close = out.bound.worst_ns - between + joint.close_ns;
  HopTimes up_split = up, down_split = down;
  up_split.worst_ns = joint.up_ns;
  down_split.worst_ns = joint.down_ns;
  tight.build(remote, up_split, down_split, up_inhibit_us, down_inhibit_us, frames_pc, frames_led);
  if (close <= tight.bound().worst_ns && tight.bound().worst_ns < out.bound.worst_ns)
    out.bound = tight.bound();
  return out;
}

LabBound arduino_control_bound(Line& line) {
  LabBound out = bound_with(line, true, 0, 0);
  if (out.ok) out.bound = timing::arduino_control_latency(out.params);
  return out;
}

}  // namespace sim
}  // namespace mb2co
