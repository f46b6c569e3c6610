#include "timing/latency.h"

#include "timing/can_bits.h"
#include "timing/time_base.h"

namespace mb2co {
namespace timing {
namespace {

constexpr uint64_t kNsPerUs = 1000;
constexpr uint16_t kIfsBits = 3;

class Builder {
 public:
  explicit Builder(LatencyBound& out) : out_(out) { out_ = LatencyBound{}; }
  void add(const char* name, uint64_t best_ns, uint64_t worst_ns) {
    add_latency_term(out_, name, best_ns, worst_ns);
  }

 private:
  LatencyBound& out_;
};

uint64_t us(uint32_t value) {
  return value * kNsPerUs;
}

uint64_t slave_end_ns(const LatencyParams& p) {
  return p.slave_waits_t35 ? t35_ns(p.serial) : 0;
}

// Inhibit wait: the previous TPDO may have left just before the event, and
// the held-back one leaves at the first loop pass after the inhibit time.
uint64_t inhibit_worst_ns(const LatencyParams& p) {
  return p.inhibit_us == 0 ? 0 : us(p.inhibit_us) + us(p.fw_loop_us);
}

// From the value being in A's OD to the LED update being noticed by A: the
// PC's poll, the read response, the PC's reaction, the write request.
void serial_round(const LatencyParams& p, Builder& b) {
  const PollCycle cycle = poll_cycle(p);
  const uint64_t loop = us(p.fw_loop_us);
  // The slave samples the OD when it notices a read; two samplings are at
  // most one cycle plus one loop pass apart.
  b.add("poll_wait", 0, cycle.period_ns + loop);
  b.add("read_response", serial_frame_ns_floor(p.serial, p.read.response_bytes), cycle.read.response_ns);
  b.add("master_end", us(p.master_end_us), us(p.master_end_us));
  b.add("pc_compute", us(p.pc_compute_us), us(p.pc_compute_us));
  b.add("write_request", serial_frame_ns_floor(p.serial, p.write.request_bytes), cycle.write.request_ns);
  b.add("slave_end", slave_end_ns(p), slave_end_ns(p));
}

// The button's Arduino sends it on (held back by the inhibit time at most).
void can_up(const LatencyParams& p, Builder& b) {
  b.add("inhibit_up", 0, inhibit_worst_ns(p));
  b.add("can_up", p.can_up_best_ns, p.can_up_worst_ns);
}

// The LED's value goes back to the LED's Arduino, which sets the LED.
void can_down(const LatencyParams& p, Builder& b) {
  b.add("inhibit_down", 0, inhibit_worst_ns(p));
  b.add("can_down", p.can_down_best_ns, p.can_down_worst_ns);
  b.add("rpdo_pass_led", 0, us(p.fw_loop_us));
}

// The press until the button's Arduino has it in its OD.
void button(const LatencyParams& p, Builder& b) {
  b.add("debounce", us(p.debounce_us), us(p.debounce_us));
  b.add("input_pass", 0, us(p.fw_loop_us));
}

}  // namespace

void add_latency_term(LatencyBound& b, const char* name, uint64_t best_ns, uint64_t worst_ns) {
  if (b.count == kMaxLatencyTerms) return;
  b.terms[b.count++] = LatencyTerm{name, best_ns, worst_ns};
  b.best_ns += best_ns;
  b.worst_ns += worst_ns;
}

PollCycle poll_cycle(const LatencyParams& p) {
  PollCycle c;
  const uint64_t loop = us(p.fw_loop_us);
  const uint64_t slave_end = slave_end_ns(p);
  const uint64_t master_end = us(p.master_end_us);
  c.read = transaction_timing(p.serial, p.read, slave_end, master_end, loop);
  c.write = transaction_timing(p.serial, p.write, slave_end, master_end, loop);
  c.busy_best_ns = c.read.best_ns + us(p.pc_compute_us) + c.write.best_ns;
  c.busy_worst_ns = c.read.worst_ns + us(p.pc_compute_us) + c.write.worst_ns;
  const uint64_t period = us(p.pc_cycle_us);
  c.period_ns = period > c.busy_worst_ns ? period : c.busy_worst_ns;
  return c;
}

LatencyBound modbus_only_latency(const LatencyParams& p) {
  LatencyBound out;
  Builder b(out);
  const uint64_t loop = us(p.fw_loop_us);
  button(p, b);
  serial_round(p, b);
  b.add("write_pass", 0, loop);
  return out;
}

LatencyBound modbus_canopen_latency(const LatencyParams& p) {
  LatencyBound out;
  Builder b(out);
  const uint64_t loop = us(p.fw_loop_us);
  button(p, b);
  can_up(p, b);
  b.add("rpdo_pass_pc", 0, loop);
  serial_round(p, b);
  b.add("write_pass", 0, loop);
  can_down(p, b);
  return out;
}

LatencyBound arduino_control_latency(const LatencyParams& p) {
  LatencyBound out;
  Builder b(out);
  button(p, b);
  can_up(p, b);
  // A's pass that takes the button PDO runs the control process (LED := button)
  // and builds its own TPDO in the same pass.
  b.add("control_pass", 0, us(p.fw_loop_us));
  can_down(p, b);
  return out;
}

uint64_t can_hop_best_ns(bool extended, uint8_t dlc, uint32_t bitrate_bps) {
  const uint16_t bits = static_cast<uint16_t>(frame_bits_unstuffed(extended, dlc) - kIfsBits);
  return ticks_to_ns_floor(bits_to_ticks(bits), bitrate_bps);
}

}  // namespace timing
}  // namespace mb2co
