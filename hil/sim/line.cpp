#include "sim/line.h"

#include <stdexcept>

#include "gateway/line_app.h"
#include "modbus/rtu_timing.h"
#include "sim/rng.h"

namespace mb2co {
namespace sim {
namespace {

// Sub-seed streams: one per purpose and station, so that adding a station
// does not reshuffle the others.
enum : uint64_t { kStreamBus = 1, kStreamLine = 2, kStreamNode = 100, kStreamPc = 300 };

// 2110h/3, 2120h/3 (gateway::NeighbourStatus).
const char* status_name(uint8_t s) {
  return s == 0      ? "unknown"
         : s == 1    ? "alive"
         : s == 2    ? "none"
         : s == 0x80 ? "unknown-unheard"
                     : "alive-unheard";
}

std::string hex_bytes(const uint8_t* d, size_t n) {
  std::string s;
  append_hex_bytes(&s, d, n);
  return s;
}

}  // namespace

void commission_write(canopen::ObjectDictionary& od, uint16_t index, uint8_t sub, uint32_t value,
                      uint16_t size) {
  uint8_t b[4];
  canopen::put_le32(b, value);
  const canopen::SdoAbort abort = od.write(index, sub, b, size);
  if (abort != canopen::kSdoOk) {
    throw std::logic_error(strf("commissioning: write %04Xh/%u = %u refused (abort %08X)", index, sub, value,
                                static_cast<uint32_t>(abort)));
  }
}

void commission_pdo(canopen::ObjectDictionary& od, uint16_t comm_index, uint16_t map_index, uint32_t entry,
                    uint32_t cob_id) {
  commission_write(od, comm_index, 1, cob_id | 0x80000000u, 4);
  commission_write(od, map_index, 0, 0, 1);
  commission_write(od, map_index, 1, entry, 4);
  commission_write(od, map_index, 0, 1, 1);
  commission_write(od, comm_index, 1, cob_id, 4);
}

Status check_line_config(const LineConfig& c) {
  if (c.stations < 2 || c.stations > 32) return Status::failure("stations must be 2..32");
  const uint32_t b = c.bitrate_kbit;
  if (b != 125 && b != 250 && b != 500 && b != 1000)
    return Status::failure("bit rate must be 125, 250, 500 or 1000 kbit/s");
  if (c.baud < 1200 || c.baud > 1000000) return Status::failure("baud must be 1200..1000000");
  if (c.node.pass_ns + c.node.loop_ns == 0)
    return Status::failure("firmware loop: a pass must take time or have a period");
  if (c.pc.cycle_ns < kNsPerMs || c.pc.cycle_ns % kNsPerMs != 0 || c.pc.cycle_ns > 1000 * kNsPerMs) {
    return Status::failure("PC cycle must be whole milliseconds, 1..1000 ms");
  }
  if (c.pc.jitter_ns >= c.pc.cycle_ns) return Status::failure("PC jitter must be below the cycle");
  if (c.debounce_ms < 1 || c.debounce_ms > 500) return Status::failure("debounce must be 1..500 ms");
  if (c.tpdo1_inhibit_100us == 0) return Status::failure("TPDO1 inhibit time must be > 0");
  if ((c.lab_pc < 0) != (c.lab_remote < 0) || c.lab_pc >= c.stations || c.lab_remote >= c.stations ||
      (c.lab_pc >= 0 && c.lab_pc == c.lab_remote)) {
    return Status::failure("lab stations must be two different stations of the line");
  }
  return Status::ok();
}

Line::Line(const LineConfig& config, EventLog* log)
    : config_(config), log_(log), rng_(mix_seed(config.seed, kStreamLine)) {
  const Status usable = check_line_config(config);
  if (!usable) throw std::invalid_argument(usable.message());
  bus_.reset(new CanBus(q_, config.bitrate_kbit * 1000u, mix_seed(config.seed, kStreamBus)));
  for (int i = 0; i < config.stations; ++i) {
    const uint64_t k = static_cast<uint64_t>(i);
    nodes_.emplace_back(
        new NodeStation(q_, *bus_, i, config.baud, config.node, mix_seed(config.seed, kStreamNode + k)));
    links_.emplace_back(new SerialLink(q_, config.baud, modbus::kRtuCharBits));
    pcs_.emplace_back(
        new PcStation(q_, i, links_.back()->to_node, config.pc, mix_seed(config.seed, kStreamPc + k)));
    NodeStation& n = *nodes_.back();
    PcStation& p = *pcs_.back();
    SerialLink& l = *links_.back();
    n.attach_serial(&l.to_node);
    p.attach_serial(&l.to_pc);
    n.serial_out = [&l](const uint8_t* d, uint16_t len) { l.to_pc.send(d, len); };
    commission(i);
  }
  wire_log();
}

void Line::commission(int i) {
  const LineConfig& c = config_;
  const uint8_t id = static_cast<uint8_t>(i + 1);
  nodes_[static_cast<size_t>(i)]->commission([&](canopen::ObjectDictionary& od) {
    commission_write(od, 0x2000, 2, c.bitrate_kbit, 2);
    commission_write(od, 0x2000, 3, c.ring ? 1 : 0, 1);
    commission_write(od, 0x2000, 4, static_cast<uint32_t>(c.stations), 1);
    commission_write(od, 0x2000, 6, c.debounce_ms, 2);
    commission_write(od, 0x1017, 0, c.heartbeat_ms, 2);
    // TPDO1 (line state): the inhibit time may change only while disabled.
    commission_write(od, 0x1800, 1, 0x80000180u + id, 4);
    commission_write(od, 0x1800, 3, c.tpdo1_inhibit_100us, 2);
    commission_write(od, 0x1800, 1, 0x180u + id, 4);
    const uint32_t lab_led = 0x62000108u;  // 6200h/1, 8 bits
    if (i == c.lab_pc) {
      commission_write(od, 0x2130, 2, static_cast<uint32_t>(c.lab_remote + 1), 1);
      commission_pdo(od, 0x1802, 0x1A02, lab_led, 0x380u + id);
    }
    if (i == c.lab_remote)
      commission_pdo(od, 0x1403, 0x1603, lab_led, 0x380u + static_cast<uint32_t>(c.lab_pc + 1));
    if (c.commission_more) c.commission_more(i, od);
  });
}

void Line::power_on_all() {
  for (int i = 0; i < size(); ++i) {
    at(q_.now() + rng_.range(0, config_.power_on_spread_ns), [this, i] { power(i, true); });
  }
}

void Line::at(SimNs t, std::function<void()> fn) {
  script_.fns.push_back(std::move(fn));
  q_.at(t, &script_, 0, script_.fns.size() - 1);
}

void Line::Script::on_event(uint32_t, uint64_t arg) {
  std::function<void()> fn = std::move(fns[static_cast<size_t>(arg)]);
  fns[static_cast<size_t>(arg)] = nullptr;
  fn();
}

void Line::set_button(int station, uint8_t button, bool pressed) {
  NodeStation& n = node(station);
  const uint8_t b =
      pressed ? static_cast<uint8_t>(n.buttons() | button) : static_cast<uint8_t>(n.buttons() & ~button);
  n.set_buttons(b);
  if (log_ && log_->enabled()) {
    const char* name = button == gateway::kStart ? "START" : button == gateway::kStop ? "STOP" : "STOP2";
    log_->add(q_.now(), station, "button", strf("%s=%d", name, pressed ? 1 : 0));
  }
  if (on_button) on_button(station, button, pressed);
}

void Line::power(int station, bool on) {
  note(station, "power", on ? "on" : "off");
  if (on)
    node(station).power_on();
  else
    node(station).power_off();
}

void Line::plug(int station, bool connected) {
  note(station, "serial", connected ? "plugged" : "unplugged");
  link(station).set_connected(connected);
}

void Line::note(int station, const char* event, const std::string& detail) {
  if (log_) log_->add(q_.now(), station, event, detail);
}

void Line::wire_log() {
  const bool logging = log_ != nullptr && log_->enabled();
  CanTrace* trace = log_ != nullptr ? log_->can_trace() : nullptr;
  bus_->observer = [this, logging, trace](const CanAttempt& a) {
    if (trace != nullptr && !a.error) trace->frame(a.end_ns, a.frame);
    if (logging) {
      log_->add(a.end_ns, a.sender, a.error ? "can_error" : "can",
                strf("id=%03X dlc=%u data=%s sof_ns=%llu bits=%u stuff=%u rx=%d", a.frame.id, a.frame.dlc,
                     hex_bytes(a.frame.data, a.frame.dlc > 8 ? 8 : a.frame.dlc).c_str(),
                     static_cast<unsigned long long>(a.sof_ns), a.bits, a.stuff_bits, a.receivers));
    }
    if (on_can) on_can(a);
  };
  if (logging) {
    bus_->on_bus_off = [this](int c, bool off) { log_->add(q_.now(), c, off ? "bus_off" : "bus_on", ""); };
  }
  for (int i = 0; i < size(); ++i) {
    node(i).on_leds = [this, logging](int s, uint8_t leds) {
      if (logging) {
        log_->add(q_.now(), s, "leds",
                  strf("self=%d prev=%d next=%d lab=%d", leds & 1, (leds >> 1) & 1, (leds >> 2) & 1,
                       (leds >> 3) & 1));
      }
      if (on_leds) on_leds(s, leds);
    };
    node(i).on_state = [this, logging](int s, const NodeState& b, const NodeState& a) {
      if (logging) {
        log_->add(q_.now(), s, "state",
                  strf("nmt=%u run=%u stop2=%u prev=%s/%u next=%s/%u", a.nmt, a.run, a.stop2_count,
                       status_name(a.prev_status), a.prev_run, status_name(a.next_status), a.next_run));
      }
      if (on_state) on_state(s, b, a);
    };
    if (logging) {
      node(i).can().on_overflow = [this, i](const CanFrame& f) {
        log_->add(q_.now(), i, "rx_overflow", strf("id=%03X", f.id));
      };
      pc(i).on_transaction = [this](int s, const uint8_t* req, uint16_t len, bool ok,
                                    modbus::ParseStatus st) {
        log_->add(q_.now(), s, "modbus",
                  strf("req=%s ok=%d status=%u", hex_bytes(req, len > 8 ? 8 : len).c_str(), ok ? 1 : 0,
                       static_cast<unsigned>(st)));
      };
    }
  }
}

}  // namespace sim
}  // namespace mb2co
