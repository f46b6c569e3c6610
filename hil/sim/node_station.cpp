#include "sim/node_station.h"

#include <algorithm>

namespace mb2co {
namespace sim {

NodeStation::NodeStation(EventQueue& queue, CanBus& bus, int index, uint32_t baud, const NodeTiming& timing,
                         uint64_t seed)
    : q_(queue),
      can_(bus, timing.can_rx_buffers),
      index_(index),
      baud_(baud),
      timing_(timing),
      rng_(seed),
      uart_(baud, timing.uart_rx_bytes) {
  can_.set_powered(false);
  can_.on_rx = [this] { floor_moved(); };  // a frame waits: the next pass calls the firmware
}

void NodeStation::power_on() {
  if (gw_) return;
  ++generation_;
  boot_ns_ = q_.now();
  can_.set_powered(true);
  SerialChar c;
  while (rx_ != nullptr && rx_->take(q_.now(), &c)) {
  }  // arrived while off: lost
  leds_out_ = 0;
  make_gateway();
  eeprom_.set_now(q_.now());
  gw_->start(0, static_cast<uint8_t>(index_ + 1));  // sends the boot-up message
  state_ = read_state();
  last_buttons_ = buttons_;
  wake_ns_ = 0;  // the first pass calls the firmware
  rest_known_ = false;
  booting_ = true;
  uart_.clear_request();
  q_.at(finish_pass(0, timing_.pass_ns), this, kPass, generation_);
}

void NodeStation::power_off() {
  if (!gw_) return;
  q_.wake(this);  // its next pass runs as the stale event it now is
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
  if (code == kPass) {
    pass();
  } else {
    release();
    floor_moved();  // the outputs left: the passes after it may be idle again
  }
}

void NodeStation::pass() {
  const SimNs t = q_.now();
  ++passes_;
  SimNs proc = timing_.pass_ns + rng_.range(0, timing_.jitter_ns);
  // Idle: the core's next deadline is ahead, and no CAN frame or button
  // change came since the firmware last ran. Serial characters may.
  const bool idle = timing_.skip_idle && t < wake_ns_ && buttons_ == last_buttons_ && can_.rx_waiting() == 0;
  const bool serial = rx_ != nullptr && rx_->ready(t);
  if (idle && !serial) {
    next_pass(finish_pass(leds_out_, proc));  // same as running it
    return;
  }
  const uint32_t now_us = micros_at(t);
  gateway::Gateway& g = *gw_;
  eeprom_.set_now(t);
  if (serial) {
    proc += take_serial(t, now_us);
    // The characters only fed the framer (nothing sent, nothing due yet).
    if (idle && serial_pending_.empty() && tx_pending_.empty()) {
      ask_deadline_after_chars(t, now_us);
      if (t < wake_ns_) {
        next_pass(finish_pass(leds_out_, proc));
        return;
      }
    }
  }
  ++firmware_calls_;
  last_buttons_ = buttons_;
  CanFrame f;
  while (can_.receive(f)) {
    proc += timing_.frame_ns;
    g.on_can_frame(f, now_us);
  }
  const uint8_t leds = g.process(now_us, buttons_);
  if (!serial_pending_.empty()) {
    proc += request_cost(timing_, uart_.request().data(), uart_.request().size());
    uart_.clear_request();
  }
  const NodeState s = read_state();
  if (s != state_) {
    const NodeState before = state_;
    state_ = s;
    if (on_state) on_state(index_, before, s);
  }
  if (timing_.skip_idle) ask_deadline(t, now_us);
  next_pass(finish_pass(leds, proc));
}

void NodeStation::next_pass(SimNs t_ns) {
  if (timing_.skip_idle)
    q_.sleep(this, t_ns, kPass, generation_);
  else
    q_.again_at(t_ns);
}

SimNs NodeStation::wake_floor() const {
  // What makes pass() call the firmware, or schedule a release (never after
  // a release has run: kept here so that such a pass runs as pass()).
  if (buttons_ != last_buttons_ || can_.rx_waiting() != 0 || !tx_pending_.empty() ||
      !serial_pending_.empty() || leds_out_ != leds_ || booting_) {
    return 0;
  }
  return rx_ != nullptr ? std::min(wake_ns_, rx_->first_end()) : wake_ns_;
}

SimNs NodeStation::idle_passes(SimNs t, SimNs limit, uint64_t* count) {
  // pass() and finish_pass() for each idle pass (timing in locals: the
  // draws' stores cannot change them).
  const SimNs pass_ns = timing_.pass_ns;
  const SimNs jitter_ns = timing_.jitter_ns;
  const SimNs loop_ns = timing_.loop_ns;
  uint64_t n = 0;
  do {
    ++n;
    const SimNs proc = pass_ns + rng_.range(0, jitter_ns);
    t += loop_ns > proc ? loop_ns : proc;
  } while (t < limit);
  passes_ += n;
  *count += n;
  return t;
}

SimNs NodeStation::take_serial(SimNs t, uint32_t now_us) {
  gateway::Gateway& g = *gw_;
  const uint32_t handed = uart_.take(*rx_, t, [&](const SerialChar& c) {
    g.on_serial_byte(c.byte, timing_.isr_stamps ? micros_at(c.end_ns) : now_us);
  });
  return timing_.byte_ns * handed;
}

void NodeStation::ask_deadline(SimNs t, uint32_t now_us) {
  uint32_t at_us = 0;
  wake_ns_ = gw_->next_deadline(now_us, &at_us) ? at_micros(t, now_us, at_us) : ~SimNs{0};
  // With no frame in progress the answer is the rest of the core's alone.
  const modbus::SlaveCore& m = gw_->modbus_slave();
  uint32_t frame_us = 0;
  rest_known_ = !m.next_deadline(now_us, &frame_us);
  rest_wake_ns_ = wake_ns_;
  rest_messages_ = m.counters().server_messages;
}

void NodeStation::ask_deadline_after_chars(SimNs t, uint32_t now_us) {
  const modbus::SlaveCore& m = gw_->modbus_slave();
  if (!rest_known_ || m.counters().server_messages != rest_messages_) return ask_deadline(t, now_us);
  uint32_t frame_us = 0;
  wake_ns_ = m.next_deadline(now_us, &frame_us) ? std::min(rest_wake_ns_, at_micros(t, now_us, frame_us))
                                                : rest_wake_ns_;
}

SimNs NodeStation::at_micros(SimNs t, uint32_t now_us, uint32_t at_us) const {
  // micros() = (t - boot) / 1 us, rounded down: it reaches at_us at the
  // start of that microsecond (wrap-safe: deadlines are < 2^31 us ahead).
  const uint32_t delta = at_us - now_us;
  if (static_cast<int32_t>(delta) <= 0) return t;
  return t - (t - boot_ns_) % kNsPerUs + SimNs{delta} * kNsPerUs;
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

}  // namespace sim
}  // namespace mb2co
