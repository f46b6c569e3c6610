#include "sim/node_station.h"

#include <algorithm>

#include "canopen/pdo_map.h"
#include "canopen/sdo_server.h"
#include "filter_plan.h"
#include "modbus/rtu_timing.h"

namespace mb2co {
namespace sim {

NodeTiming uno_timing() { return NodeTiming(); }

NodeTiming fast_timing() {
  NodeTiming t;
  t.loop_ns = 1000 * kNsPerUs;
  t.pass_ns = 100 * kNsPerUs;
  t.jitter_ns = 200 * kNsPerUs;
  t.frame_ns = t.byte_ns = t.request_ns = t.write_ns = t.item_ns = t.item_address_ns = 0;
  return t;
}

SimNs request_cost(const NodeTiming& t, const uint8_t* req, size_t len) {
  if (len < 6) return t.request_ns;
  const uint8_t fc = req[1];
  const uint32_t start = (uint32_t{req[2]} << 8) | req[3];
  uint32_t count = (uint32_t{req[4]} << 8) | req[5];
  const bool single_write = fc == 0x05 || fc == 0x06;
  if (single_write) count = 1;
  if (fc > 0x06 && fc != 0x0F && fc != 0x10) return t.request_ns;
  if (count > 2000) count = 2000;
  const SimNs per_item = t.item_ns + (fc >= 0x05 ? t.write_ns : 0);
  return t.request_ns + per_item * count + t.item_address_ns * start;
}

SimNs max_pass_ns(const NodeTiming& t, size_t frames, size_t bytes, SimNs request) {
  return t.pass_ns + t.jitter_ns + t.frame_ns * frames + t.byte_ns * bytes + request;
}

NodeStation::NodeStation(EventQueue& queue, CanBus& bus, int index, uint32_t baud,
                         const NodeTiming& timing, uint64_t seed)
    : q_(queue),
      can_(bus, timing.can_rx_buffers),
      index_(index),
      baud_(baud),
      timing_(timing),
      rng_(seed),
      eeprom_(1024, 0xFF) {
  storage_ = canopen::ParamStorage{&NodeStation::eeprom_read, &NodeStation::eeprom_write, this};
  can_.set_powered(false);
  const modbus::RtuTiming rtu = modbus::rtu_timing(baud);
  frame_gap_ns_ = (rtu.t35_us + rtu.char_us) * kNsPerUs;
}

void NodeStation::make_gateway() {
  gateway::GatewayPorts ports{CanSink{&NodeStation::can_send, this},
                              modbus::ByteSink{&NodeStation::serial_send, this}, &storage_, baud_};
  gw_.reset(new gateway::Gateway(ports));
  if (!timing_.isr_stamps) gw_->modbus_slave().set_check_t15(false);
  canopen::ObjectDictionary& od = gw_->od();
  const uint16_t rows[7] = {od.find(0x2002, 0), od.find(0x2100, 2), od.find(0x2100, 3),
                            od.find(0x2110, 3), od.find(0x2120, 3), od.find(0x2110, 1),
                            od.find(0x2120, 1)};
  std::copy(rows, rows + 7, rows_);
  wr_.sync_period = od.find(0x1006, 0);
  wr_.emcy_inhibit = od.find(0x1015, 0);
  wr_.debounce = od.find(0x2000, 6);
  wr_.watchdog = od.find(0x2000, 9);
  wr_.guard_time = od.find(0x100C, 0);
  wr_.life_factor = od.find(0x100D, 0);
  wr_.heartbeat = od.find(0x1017, 0);
  for (uint16_t k = 0; k < 4; ++k) {
    const uint16_t comm = static_cast<uint16_t>(0x1800 + k);
    tpdo_cob_rows_[k] = od.find(comm, 1);
    wr_.tpdo_type[k] = od.find(comm, 2);
    wr_.tpdo_inhibit[k] = od.find(comm, 3);
    wr_.tpdo_event[k] = od.find(comm, 5);
    wr_.tpdo_map[k] = od.find(static_cast<uint16_t>(0x1A00 + k), 0);
    wr_.rpdo_event[k] = od.find(static_cast<uint16_t>(0x1400 + k), 5);
    wr_.consumer[k] = od.find(0x1016, static_cast<uint8_t>(k + 1));
  }
  values_ = nullptr;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    uint8_t* v = od.ram(r);
    if (v != nullptr && (values_ == nullptr || v < values_)) values_ = v;
  }
  values_before_.assign(od.definition().values_size, 0);
  wc_valid_ = false;
  requests_seen_ = 0;
  request_seen_ns_ = 0;
  sdo_heard_ns_ = 0;
}

void NodeStation::commission(const std::function<void(canopen::ObjectDictionary&)>& configure) {
  bench_ = true;
  make_gateway();
  gw_->start(0, static_cast<uint8_t>(index_ + 1));
  if (configure) configure(gw_->od());
  uint8_t save[4];
  canopen::put_le32(save, canopen::kSaveSignature);
  gw_->od().write(0x1010, 1, save, 4);
  gw_.reset();
  bench_ = false;
  tx_pending_.clear();
  serial_pending_.clear();
}

void NodeStation::power_on() {
  if (gw_) return;
  ++generation_;
  boot_ns_ = q_.now();
  can_.set_powered(true);
  SerialChar c;
  while (rx_ != nullptr && rx_->take(q_.now(), &c)) {}  // arrived while off: lost
  leds_out_ = 0;
  make_gateway();
  gw_->start(0, static_cast<uint8_t>(index_ + 1));  // sends the boot-up message
  state_ = read_state();
  plan_filters();
  quiet_ = false;
  holdoff_ns_ = q_.now() + kNsPerS;
  hb_sent_prev_ns_ = 0;
  std::fill(tpdo_sent_ns_, tpdo_sent_ns_ + 4, 0);
  std::fill(hb_heard_ns_, hb_heard_ns_ + 128, 0);
  booting_ = true;
  frame_.clear();
  q_.at(finish_pass(0, timing_.pass_ns), this, kPass, generation_);
}

void NodeStation::power_off() {
  if (!gw_) return;
  ++generation_;
  gw_.reset();
  can_.set_powered(false);
  tx_pending_.clear();
  serial_pending_.clear();
  if (leds_ != 0) {
    leds_ = 0;
    if (on_leds) on_leds(index_, 0);
  }
}

void NodeStation::on_event(uint32_t code, uint64_t arg) {
  if (arg != generation_ || !gw_) return;  // from before a power cycle
  if (code == kPass) pass();
  else release();
}

void NodeStation::pass() {
  const SimNs t = q_.now();
  prev_pass_ns_ = pass_ns_;
  pass_ns_ = t;
  ++passes_;
  SimNs proc = timing_.pass_ns + rng_.range(0, timing_.jitter_ns);
  // Idle: process() now would do nothing (compute_wake), and no CAN frame or
  // button change came since the firmware last ran. Serial characters may.
  const bool idle = timing_.skip_idle && quiet_ && t < wake_ns_ && buttons_ == last_buttons_ &&
                    can_.rx_waiting() == 0;
  const bool serial = rx_ != nullptr && rx_->ready(t);
  if (idle && !serial) {
    q_.again_at(finish_pass(leds_out_, proc));  // same as running it
    return;
  }
  const uint32_t now_us = micros_at(t);
  gateway::Gateway& g = *gw_;
  if (timing_.skip_idle) std::copy(values_, values_ + values_before_.size(), values_before_.begin());
  refused_ = false;
  if (serial) {
    const SlaveSnapshot before = slave_snapshot();
    proc += take_serial(t, now_us);
    if (idle && slave_snapshot() == before && serial_idle(t, now_us)) {
      q_.again_at(finish_pass(leds_out_, proc));
      return;
    }
  }
  ++firmware_calls_;
  if (buttons_ != last_buttons_) {
    last_buttons_ = buttons_;
    buttons_changed_ns_ = t;
  }
  CanFrame f;
  while (can_.receive(f)) {
    proc += timing_.frame_ns;
    if (f.id > 0x700 && f.id < 0x780 && !f.extended()) hb_heard_ns_[f.id - 0x700] = t;
    if (f.id == 0x600u + g.node_id()) sdo_heard_ns_ = t;
    g.on_can_frame(f, now_us);
  }
  const uint8_t leds = g.process(now_us, buttons_);
  const uint16_t requests = g.modbus_slave().counters().server_messages;
  if (requests != requests_seen_) {  // as LineApp::process saw it (watchdog)
    requests_seen_ = requests;
    request_seen_ns_ = t;
  }
  if (!serial_pending_.empty()) {
    proc += request_cost(timing_, frame_.data(), frame_.size());
    frame_.clear();
  }
  const NodeState s = read_state();
  // Characters taken are no change by themselves: the framer's only timer
  // (t3.5) is among those compute_wake reads.
  bool changed = !tx_pending_.empty() || !serial_pending_.empty() || leds != leds_ || refused_;
  if (s != state_) {
    const NodeState before = state_;
    state_ = s;
    changed = true;
    if (s.nmt != before.nmt) {
      holdoff_ns_ = t + kNsPerS;  // timers restart after a reset or a state change
      if (s.nmt != canopen::kNmtOperational) {  // a reset: its sends are yet to come
        hb_sent_prev_ns_ = 0;
        std::fill(tpdo_sent_ns_, tpdo_sent_ns_ + 4, 0);
        plan_filters();
      }
    }
    if (on_state) on_state(index_, before, s);
  }
  if (timing_.skip_idle) {
    if (!std::equal(values_before_.begin(), values_before_.end(), values_)) {
      changed = true;
      wc_valid_ = false;
    }
    quiet_ = !changed;
    if (quiet_) wake_ns_ = compute_wake(t);
  }
  q_.again_at(finish_pass(leds, proc));
}

SimNs NodeStation::take_serial(SimNs t, uint32_t now_us) {
  gateway::Gateway& g = *gw_;
  SimNs proc = 0;
  SerialChar c;
  uint32_t taken = 0;
  while (rx_->take(t, &c)) {
    if (++taken > timing_.uart_rx_bytes) {  // the ring was full: dropped
      ++uart_overruns_;
      continue;
    }
    if (c.end_ns - last_char_ns_ > frame_gap_ns_ || frame_.size() >= 256) frame_.clear();
    frame_.push_back(c.byte);
    last_char_ns_ = c.end_ns;
    proc += timing_.byte_ns;
    g.on_serial_byte(c.byte, timing_.isr_stamps ? micros_at(c.end_ns) : now_us);
  }
  return proc;
}

NodeStation::SlaveSnapshot NodeStation::slave_snapshot() const {
  const modbus::SlaveCore& m = gw_->modbus_slave();
  return SlaveSnapshot{m.counters(), m.stats(), m.listen_only()};
}

bool NodeStation::serial_idle(SimNs t, uint32_t now_us) {
  uint32_t slave_us = 0;
  if (!gw_->modbus_slave().deadline(slave_us)) return true;
  SimNs wake = ~SimNs{0};
  lower_wake(wake, t, at_micros(t, now_us, slave_us));
  if (t >= wake) return false;
  if (wake < wake_ns_) wake_ns_ = wake;
  return true;
}

void NodeStation::lower_wake(SimNs& wake, SimNs t, SimNs exact) {
  // 1 µs margin for the µs clock's rounding. A deadline already behind `t`
  // was handled by this pass or an earlier one (a pass is never skipped
  // past a wake time).
  if (exact + kNsPerUs <= t) return;
  const SimNs w = exact > kNsPerUs ? exact - kNsPerUs : 0;
  if (w < wake) wake = w;
}

SimNs NodeStation::at_micros(SimNs t, uint32_t now_us, uint32_t at_us) const {
  // When micros() reaches at_us (wrap-safe: deadlines are < 35 min ahead).
  const uint32_t delta = at_us - now_us;
  if (static_cast<int32_t>(delta) <= 0) return t;
  return t - (t - boot_ns_) % kNsPerUs + SimNs{delta} * kNsPerUs;
}

void NodeStation::read_wake_config() {
  const canopen::ObjectDictionary& od = gw_->od();
  WakeConfig& c = wc_;
  c = WakeConfig{};
  c.untracked = od.get(wr_.sync_period) != 0 || od.get(wr_.emcy_inhibit) != 0;
  c.debounce_ns = od.get(wr_.debounce) * kNsPerMs;
  c.watchdog_us = od.get(wr_.watchdog) * 1000u;
  c.heartbeat_ns = od.get(wr_.heartbeat) * kNsPerMs;
  auto value = [&](uint16_t row) { return row != canopen::ObjectDictionary::kNoRow ? od.get(row) : 0u; };
  if (c.heartbeat_ns == 0 && value(wr_.guard_time) != 0 && value(wr_.life_factor) != 0) c.untracked = true;
  for (size_t n = 0; n < 4; ++n) {
    if ((od.get(tpdo_cob_rows_[n]) & 0x80000000u) || od.get(wr_.tpdo_map[n]) == 0) continue;
    if (od.get(wr_.tpdo_type[n]) < 254) c.untracked = true;
    c.tpdo_inhibit_ns[n] = od.get(wr_.tpdo_inhibit[n]) * 100 * kNsPerUs;
    c.tpdo_event_ns[n] = od.get(wr_.tpdo_event[n]) * kNsPerMs;
  }
  for (size_t n = 0; n < 4; ++n) {
    if (od.get(wr_.rpdo_event[n]) != 0) c.untracked = true;
  }
  for (size_t k = 0; k < 4; ++k) {
    const uint32_t e = od.get(wr_.consumer[k]);
    const uint32_t node = (e >> 16) & 0x7Fu;
    if ((e & 0xFFFFu) == 0 || node == 0) continue;
    c.consumer_node[k] = static_cast<uint8_t>(node);
    c.consumer_ns[k] = (e & 0xFFFFu) * kNsPerMs;
  }
  wc_valid_ = true;
}

// Every timer the firmware keeps, as its configuration and the frames seen
// tell: Modbus frame end (the slave's own deadline), debounce, Modbus
// watchdog, SDO server timeout, heartbeat producer, TPDO inhibit and event
// timers, heartbeat consumers, the blink of an unknown neighbour. Anything
// not tracked (SYNC, EMCY inhibit, RPDO timeouts, synchronous TPDOs, life
// guarding, the first second after a reset) disables skipping. The tests
// Determinism.SkippingIdlePasses* check the result against running every
// pass.
SimNs NodeStation::compute_wake(SimNs t) {
  if (t < holdoff_ns_) return t;
  if (!wc_valid_) read_wake_config();
  const WakeConfig& c = wc_;
  if (c.untracked) return t;
  const uint32_t now_us = micros_at(t);
  SimNs wake = ~SimNs{0};
  auto due = [&](SimNs exact) { lower_wake(wake, t, exact); };
  uint32_t slave_us = 0;
  if (gw_->modbus_slave().deadline(slave_us)) due(at_micros(t, now_us, slave_us));
  due(buttons_changed_ns_ + c.debounce_ns);
  // Modbus watchdog: the line application stops the station in the first
  // pass with micros() - (micros() of the pass that saw the last request) >
  // 2000h/9 ms (armed once a request was seen; a past deadline has fired).
  if (c.watchdog_us != 0 && request_seen_ns_ != 0) {
    due(request_seen_ns_ - (request_seen_ns_ - boot_ns_) % kNsPerUs + (SimNs{c.watchdog_us} + 1) * kNsPerUs);
  }
  // SDO server: a transfer in progress times out a fixed time after the
  // request that last reached it.
  if (sdo_heard_ns_ != 0) {
    due(sdo_heard_ns_ - (sdo_heard_ns_ - boot_ns_) % kNsPerUs +
        SimNs{canopen::SdoServer::kDefaultTimeoutUs} * kNsPerUs);
  }
  // Heartbeat producer: deadlines d, d + P, ...; the last one passed lies
  // after the pass before the one that sent it, so the next one after that + P.
  if (c.heartbeat_ns != 0) {
    if (hb_sent_prev_ns_ == 0 || hb_sent_prev_ns_ + c.heartbeat_ns <= t) return t;
    due(hb_sent_prev_ns_ + c.heartbeat_ns + kNsPerUs);
  }
  for (size_t n = 0; n < 4; ++n) {
    if (c.tpdo_inhibit_ns[n] + c.tpdo_event_ns[n] == 0) continue;  // off or nothing timed
    if (tpdo_sent_ns_[n] == 0) return t;
    if (c.tpdo_inhibit_ns[n] != 0) due(tpdo_sent_ns_[n] + c.tpdo_inhibit_ns[n]);
    if (c.tpdo_event_ns[n] != 0) due(tpdo_sent_ns_[n] + c.tpdo_event_ns[n]);
  }
  for (size_t k = 0; k < 4; ++k) {
    const SimNs heard = hb_heard_ns_[c.consumer_node[k]];
    if (c.consumer_ns[k] == 0 || heard == 0) continue;
    due(heard + c.consumer_ns[k]);
  }
  if (state_.prev_status == gateway::kNeighbourUnknown || state_.next_status == gateway::kNeighbourUnknown) {
    const uint32_t half = gateway::LineApp::kBlinkHalfPeriodUs;
    due(at_micros(t, now_us, (now_us / half + 1) * half));
  }
  return wake;
}

SimNs NodeStation::finish_pass(uint8_t leds, SimNs proc) {
  const SimNs t = q_.now();
  leds_out_ = leds;
  if (!tx_pending_.empty() || !serial_pending_.empty() || leds != leds_) {
    q_.at(t + proc, this, kRelease, generation_);
  }
  SimNs next = proc;
  if (timing_.loop_ns != 0 && timing_.loop_ns > proc) next = timing_.loop_ns;
  // Start-up takes a different time on every board: the first loop pass
  // comes after a random extra delay, so that stations are not in step.
  if (booting_) next = proc + rng_.range(0, timing_.loop_ns != 0 ? timing_.loop_ns : timing_.pass_ns);
  booting_ = false;
  return t + next;
}

void NodeStation::release() {
  for (const CanFrame& f : tx_pending_) can_.send(f);
  tx_pending_.clear();
  if (!serial_pending_.empty()) {
    if (serial_out) serial_out(serial_pending_.data(), static_cast<uint16_t>(serial_pending_.size()));
    serial_pending_.clear();
  }
  if (leds_out_ != leds_) {
    leds_ = leds_out_;
    if (on_leds) on_leds(index_, leds_);
  }
}

void NodeStation::plan_filters() {
  if (!timing_.can_filters) return;
  canopen::ObjectDictionary& od = gw_->od();
  const uint8_t id = gw_->node_id();
  uint16_t ids[mcp2515::kMaxSubscribedIds];
  uint8_t n = 0;
  auto add = [&](uint32_t cob) {
    if (n < mcp2515::kMaxSubscribedIds) ids[n++] = static_cast<uint16_t>(cob & 0x7FFu);
  };
  add(0x000);         // NMT
  add(0x600u + id);   // SDO requests
  for (uint16_t k = 0; k < 4; ++k) {
    const uint32_t cob = od.get(od.find(static_cast<uint16_t>(0x1400 + k), 1));
    if (!(cob & 0x80000000u)) add(cob);
  }
  for (uint8_t sub = 1; sub <= 2; ++sub) {
    const uint16_t row = od.find(0x1016, sub);
    if (row == canopen::ObjectDictionary::kNoRow) continue;
    const uint32_t e = od.get(row);
    if ((e & 0xFFFFu) != 0 && ((e >> 16) & 0x7Fu) != 0) add(0x700u + ((e >> 16) & 0x7Fu));
  }
  mcp2515::FilterPlan plan;
  if (mcp2515::plan_filters(ids, n, plan)) can_.set_acceptance(&plan);
}

NodeState NodeStation::read_state() {
  const canopen::ObjectDictionary& od = gw_->od();
  NodeState s;
  s.nmt = static_cast<uint8_t>(od.get(rows_[0]));
  s.run = static_cast<uint8_t>(od.get(rows_[1]));
  s.stop2_count = static_cast<uint16_t>(od.get(rows_[2]));
  s.prev_status = static_cast<uint8_t>(od.get(rows_[3]));
  s.next_status = static_cast<uint8_t>(od.get(rows_[4]));
  s.prev_run = static_cast<uint8_t>(od.get(rows_[5]));
  s.next_run = static_cast<uint8_t>(od.get(rows_[6]));
  return s;
}

bool NodeStation::can_send(void* ctx, const CanFrame& f) {
  NodeStation& n = *static_cast<NodeStation*>(ctx);
  if (n.bench_) return true;
  if (n.can_.free_tx() <= static_cast<int>(n.tx_pending_.size())) {
    n.refused_ = true;
    return false;
  }
  n.tx_pending_.push_back(f);
  if (n.gw_ && f.id == 0x700u + n.gw_->node_id()) n.hb_sent_prev_ns_ = n.prev_pass_ns_ != 0 ? n.prev_pass_ns_ : 1;
  for (int k = 0; k < 4 && n.gw_; ++k) {
    const uint32_t cob = n.gw_->od().get(n.tpdo_cob_rows_[k]);
    if (!(cob & 0x80000000u) && f.id == (cob & 0x7FFu)) n.tpdo_sent_ns_[k] = n.pass_ns_;
  }
  return true;
}

bool NodeStation::serial_send(void* ctx, const uint8_t* data, uint16_t len) {
  NodeStation& n = *static_cast<NodeStation*>(ctx);
  if (!n.bench_) n.serial_pending_.insert(n.serial_pending_.end(), data, data + len);
  return true;
}

bool NodeStation::eeprom_read(void* ctx, uint16_t at, uint8_t* data, uint16_t len) {
  NodeStation& n = *static_cast<NodeStation*>(ctx);
  if (size_t{at} + len > n.eeprom_.size()) return false;
  std::copy(n.eeprom_.begin() + at, n.eeprom_.begin() + at + len, data);
  return true;
}

bool NodeStation::eeprom_write(void* ctx, uint16_t at, const uint8_t* data, uint16_t len) {
  NodeStation& n = *static_cast<NodeStation*>(ctx);
  if (size_t{at} + len > n.eeprom_.size()) return false;
  std::copy(data, data + len, n.eeprom_.begin() + at);
  return true;
}

}  // namespace sim
}  // namespace mb2co
