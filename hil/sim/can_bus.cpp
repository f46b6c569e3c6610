#include "sim/can_bus.h"

#include "timing/can_bits.h"

namespace mb2co {
namespace sim {
namespace {

/// Bits in the order they meet on the wire: base id, RTR/SRR, IDE, then the
/// 18 extension bits and RTR of an extended frame. Lower wins.
uint32_t wire_key(const CanFrame& f) {
  const uint32_t rtr = f.rtr() ? 1u : 0u;
  if (!f.extended()) return ((f.id & 0x7FFu) << 21) | (rtr << 20);
  const uint32_t base = (f.id >> 18) & 0x7FFu;
  return (base << 21) | (1u << 20) | (1u << 19) | ((f.id & 0x3FFFFu) << 1) | rtr;
}

constexpr uint16_t kIfsBits = 3;
constexpr uint16_t kErrorFrameBits = 6 + 6 + 8 + kIfsBits;  // flag, echo, delimiter, IFS
constexpr uint16_t kRecoveryBits = 128 * 11;
constexpr uint16_t kErrorPassive = 128;
constexpr uint16_t kBusOff = 256;

}  // namespace

// ---- controller -------------------------------------------------------------

CanController::CanController(CanBus& bus, size_t rx_buffers) : bus_(bus), rx_(rx_buffers) {
  index_ = bus.attach(this);
}

int CanController::free_tx() const {
  int n = 0;
  for (const TxBuf& b : tx_) n += b.used ? 0 : 1;
  return powered_ ? n : 0;
}

bool CanController::send(const CanFrame& f) {
  if (!powered_ || f.dlc > 8) {
    ++counters_.tx_refused;
    return false;
  }
  for (TxBuf& b : tx_) {
    if (b.used) continue;
    b = TxBuf{f, wire_key(f), tx_seq_++, true};
    if (on_bus()) bus_.request();
    return true;
  }
  ++counters_.tx_refused;
  return false;
}

int CanController::next_tx() const {
  int best = -1;
  for (int i = 0; i < kTxBuffers; ++i) {
    const TxBuf& b = tx_[i];
    if (!b.used) continue;
    if (best < 0 || b.key < tx_[best].key || (b.key == tx_[best].key && b.seq < tx_[best].seq)) best = i;
  }
  return best;
}

bool CanController::receive(CanFrame& f) {
  if (rx_count_ == 0) return false;
  f = rx_[rx_head_];
  rx_head_ = (rx_head_ + 1) % rx_.size();
  --rx_count_;
  return true;
}

void CanController::set_acceptance(const mcp2515::FilterPlan* plan) {
  filtered_ = plan != nullptr;
  if (plan) plan_ = *plan;
}

void CanController::deliver(const CanFrame& f) {
  if (rec_ > 0) --rec_;  // a correct frame counts whether it is accepted or not
  update_state();
  if (filtered_ && (f.extended() || !mcp2515::plan_accepts(plan_, static_cast<uint16_t>(f.id)))) {
    ++counters_.rx_filtered;
    return;
  }
  ++counters_.rx_ok;
  if (rx_count_ == rx_.size()) {
    ++counters_.rx_overflows;
    if (on_overflow) on_overflow(f);
    return;
  }
  rx_[(rx_head_ + rx_count_) % rx_.size()] = f;
  ++rx_count_;
  if (on_rx) on_rx();
}

void CanController::set_powered(bool on) {
  if (on == powered_) return;
  powered_ = on;
  ++generation_;
  for (TxBuf& b : tx_) b.used = false;
  rx_head_ = rx_count_ = 0;
  tec_ = rec_ = 0;
  state_ = CanErrorState::kActive;
}

void CanController::count_tx_error() {
  ++counters_.tx_errors;
  tec_ = static_cast<uint16_t>(tec_ + 8);
  update_state();
}

void CanController::count_rx_error() {
  if (rec_ < kErrorPassive) ++rec_;
  update_state();
}

void CanController::update_state() {
  if (state_ == CanErrorState::kBusOff) return;
  if (tec_ >= kBusOff) {
    state_ = CanErrorState::kBusOff;
    ++counters_.bus_offs;
    bus_.schedule_recovery(*this);
    return;
  }
  state_ =
      (tec_ >= kErrorPassive || rec_ >= kErrorPassive) ? CanErrorState::kPassive : CanErrorState::kActive;
}

// ---- bus --------------------------------------------------------------------

CanBus::CanBus(EventQueue& queue, uint32_t bitrate_bps, uint64_t seed)
    : q_(queue), bitrate_bps_(bitrate_bps), bit_ns_(kNsPerS / bitrate_bps), rng_(seed) {}

int CanBus::attach(CanController* c) {
  controllers_.push_back(c);
  return static_cast<int>(controllers_.size() - 1);
}

void CanBus::request() {
  if (state_ != State::kIdle) return;  // joins at the next arbitration
  state_ = State::kArbitrating;
  current_.sof_ns = q_.now();
  q_.at(q_.now() + bit_ns_, this, kArbitrate);
}

void CanBus::schedule_recovery(CanController& c) {
  if (on_bus_off) on_bus_off(c.index(), true);
  q_.at(q_.now() + SimNs{kRecoveryBits} * bit_ns_, this, kRecover,
        (uint64_t{c.generation_} << 32) | static_cast<uint32_t>(c.index()));
}

void CanBus::on_event(uint32_t code, uint64_t arg) {
  switch (code) {
    case kArbitrate:
      arbitrate();
      break;
    case kEnd:
      finish();
      break;
    case kFree: {
      state_ = State::kIdle;
      for (CanController* c : controllers_) {
        if (c->on_bus() && c->next_tx() >= 0) {
          request();
          break;
        }
      }
      break;
    }
    case kRecover: {
      CanController& c = *controllers_[static_cast<size_t>(arg & 0xFFFFFFFFu)];
      if (c.generation_ != (arg >> 32) || c.state_ != CanErrorState::kBusOff) break;
      c.state_ = CanErrorState::kActive;
      c.tec_ = c.rec_ = 0;
      if (on_bus_off) on_bus_off(c.index(), false);
      if (c.next_tx() >= 0) request();
      break;
    }
    default:
      break;
  }
}

void CanBus::arbitrate() {
  CanController* winner = nullptr;
  int buf = -1;
  for (CanController* c : controllers_) {
    if (!c->on_bus()) continue;
    const int b = c->next_tx();
    if (b < 0) continue;
    if (winner == nullptr || c->tx_[b].key < winner->tx_[buf].key) {
      winner = c;
      buf = b;
    }
  }
  if (winner == nullptr) {  // the requester lost power during SOF
    state_ = State::kIdle;
    return;
  }
  state_ = State::kBusy;
  const CanFrame& f = winner->tx_[buf].frame;
  const timing::ExactFrameBits bits = frame_bits_.of(f);
  current_.sender = winner->index();
  current_.frame = f;
  current_.bits = bits.total_bits;
  current_.stuff_bits = bits.stuff_bits;
  current_.receivers = 0;
  current_buf_ = buf;
  current_gen_ = winner->generation_;

  int listeners = 0;
  for (CanController* c : controllers_) listeners += (c != winner && c->on_bus()) ? 1 : 0;
  const uint16_t eof_bits = static_cast<uint16_t>(bits.total_bits - kIfsBits);
  uint16_t error_bit = 0;  // bit (from SOF) where an error is signalled; 0 = none
  ack_error_ = false;
  if (winner->tx_broken_) {
    error_bit = f.extended() ? 33 : 13;  // bit error right after arbitration
  } else if (rng_.chance_ppm(corruption_ppm_)) {
    error_bit = static_cast<uint16_t>(rng_.range(1, eof_bits - 2u));
  } else if (listeners == 0) {
    error_bit = static_cast<uint16_t>(eof_bits - 9u);  // nobody acknowledges
    ack_error_ = true;
  }
  current_.error = error_bit != 0;
  if (current_.error) {
    current_.end_ns = current_.sof_ns + SimNs{error_bit} * bit_ns_;
    current_.free_ns = current_.end_ns + SimNs{kErrorFrameBits} * bit_ns_;
  } else {
    current_.end_ns = current_.sof_ns + SimNs{eof_bits} * bit_ns_;
    current_.free_ns = current_.sof_ns + SimNs{bits.total_bits} * bit_ns_;
  }
  q_.at(current_.end_ns, this, kEnd);
}

void CanBus::finish() {
  CanController& sender = *controllers_[static_cast<size_t>(current_.sender)];
  if (sender.generation_ != current_gen_ && !current_.error) {
    // The sender lost power mid-frame: the rest of the frame never came.
    current_.error = true;
    current_.free_ns = current_.end_ns + SimNs{kErrorFrameBits} * bit_ns_;
  }
  busy_ns_ += current_.free_ns - current_.sof_ns;
  if (current_.error) {
    ++error_frames_;
    if (ack_error_) ++ack_error_frames_;
    // An acknowledgement error of an error-passive sender does not count.
    const bool ack_only = ack_error_ && sender.state_ == CanErrorState::kPassive;
    if (sender.generation_ == current_gen_ && !ack_only) sender.count_tx_error();
    for (CanController* c : controllers_) {
      if (c != &sender && c->on_bus()) c->count_rx_error();
    }
  } else {
    ++frames_ok_;
    sender.tx_[current_buf_].used = false;
    ++sender.counters_.tx_ok;
    if (sender.tec_ > 0) --sender.tec_;
    sender.update_state();
    for (CanController* c : controllers_) {
      if (c == &sender || !c->on_bus()) continue;
      c->deliver(current_.frame);
      ++current_.receivers;
    }
  }
  if (observer) observer(current_);
  q_.at(current_.free_ns, this, kFree);
}

}  // namespace sim
}  // namespace mb2co
