#include "can_wire.h"

#include "bit_timing.h"
#include "timing/can_bits.h"

namespace mb2co {
namespace uno {

bool wins_arbitration(const CanFrame& a, const CanFrame& b) {
  // The arbitration field bit by bit: 11 base-id bits, then SRR/RTR (an
  // extended frame's SRR is recessive like a remote frame's RTR), IDE, the
  // 18 extension bits, RTR. Dominant (0) wins at the first difference.
  auto key = [](const CanFrame& f) {
    const uint64_t base = f.extended() ? (f.id >> 18) & 0x7FFu : f.id & 0x7FFu;
    const uint64_t srr_rtr = f.extended() || f.rtr() ? 1u : 0u;
    const uint64_t ide = f.extended() ? 1u : 0u;
    const uint64_t ext = f.extended() ? f.id & 0x3FFFFu : 0u;
    const uint64_t rtr = f.extended() && f.rtr() ? 1u : 0u;
    return (base << 21) | (srr_rtr << 20) | (ide << 19) | (ext << 1) | rtr;
  };
  return key(a) < key(b);
}

CanWire::CanWire(uint32_t cpu_hz) : cpu_hz_(cpu_hz) {}

uint64_t CanWire::frame_cycles(const CanFrame& frame) const {
  const uint64_t bits = timing::frame_bits_exact(frame).total_bits;
  const uint64_t bps = chip_.bitrate_bps(mcp2515::kOscillatorHz);
  return (bits * cpu_hz_ + bps - 1u) / bps;
}

void CanWire::frame_from_bus(const CanFrame& frame, uint64_t now, uint64_t arrival) {
  if (arrival < now) arrival = now;
  if (!inbound_.empty() && arrival < inbound_.back().arrival) arrival = inbound_.back().arrival;
  inbound_.push_back(Inbound{frame, arrival});
  advance(now);
}

uint64_t CanWire::next_event() const {
  if (busy_until_ != kIdle || inbound_.empty()) return busy_until_;
  return inbound_.front().arrival;
}

void CanWire::advance(uint64_t now) {
  uint64_t start = now;
  if (busy_until_ != kIdle) {
    if (now < busy_until_) return;
    start = busy_until_;  // the next frame follows right after the interframe space
    busy_until_ = kIdle;
    if (on_wire_outbound_) {
      chip_.bus.clear();
      if (chip_.transmit(1) == 1 && !chip_.bus.empty()) sent_.push_back(Sent{start, chip_.bus.back()});
      chip_.bus.clear();
    } else {
      const int buffer = chip_.receive_from_bus(on_wire_);
      if (buffer < 0) ++rx_dropped_;
      if (buffer == -2) ++rx_overflowed_;
    }
  }
  CanFrame out{};
  const bool have_out = chip_.next_transmit(&out);
  // The frames from outside that have reached the bus by now contend for
  // the wire, the chip's with them; one still to come leaves the wire to the
  // chip or idle. Of those waiting the lowest identifier goes first, as on a
  // bus where they come from several nodes: a remote node's SDO response is
  // not held up behind a backlog of lower-priority traffic.
  std::deque<Inbound>::iterator in = inbound_.end();
  for (auto i = inbound_.begin(); i != inbound_.end() && i->arrival <= now; ++i) {
    if (in == inbound_.end() || wins_arbitration(i->frame, in->frame)) in = i;
  }
  const bool have_in = in != inbound_.end();
  if (!have_out && !have_in) return;
  on_wire_outbound_ = have_out && (!have_in || wins_arbitration(out, in->frame));
  if (on_wire_outbound_) {
    on_wire_ = out;
  } else {
    on_wire_ = in->frame;
    if (in->arrival > start) start = in->arrival;
    inbound_.erase(in);
    ++carried_in_;
  }
  const uint64_t cycles = frame_cycles(on_wire_);
  busy_cycles_ += cycles;
  busy_until_ = start + cycles;
}

std::vector<CanWire::Sent> CanWire::take_sent() {
  std::vector<Sent> out;
  out.swap(sent_);
  return out;
}

}  // namespace uno
}  // namespace mb2co
