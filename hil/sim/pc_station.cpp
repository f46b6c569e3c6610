#include "sim/pc_station.h"

#include "modbus/protocol.h"

namespace mb2co {
namespace sim {

PcStation::PcStation(EventQueue& queue, int index, UartChannel& to_node, const PcTiming& timing,
                     uint64_t seed)
    : q_(queue), index_(index), tx_(to_node), timing_(timing), rng_(seed) {}

void PcStation::start() {
  if (running_) return;
  running_ = true;
  ++generation_;
  busy_ = awaiting_ = start_when_free_ = false;
  nominal_ns_ = q_.now() + rng_.range(0, timing_.cycle_ns - 1);
  q_.at(nominal_ns_ + rng_.range(0, timing_.jitter_ns), this, kCycle, generation_);
}

void PcStation::stop() {
  running_ = false;
  ++generation_;
  busy_ = awaiting_ = start_when_free_ = false;
}

void PcStation::on_event(uint32_t code, uint64_t arg) {
  if ((arg & 0xFFFFFFFFu) != generation_ || !running_) return;
  switch (code) {
    case kCycle:
      nominal_ns_ += timing_.cycle_ns;
      q_.at(nominal_ns_ + rng_.range(0, timing_.jitter_ns), this, kCycle, generation_);
      ++counters_.cycles;
      if (busy_) {
        if (!start_when_free_) ++counters_.overruns;
        start_when_free_ = true;
      } else {
        begin_cycle();
      }
      break;
    case kTimeout:
      if (awaiting_ && (arg >> 32) == txn_) complete(true);
      break;
    case kSend:
      send_request();
      break;
    default:
      break;
  }
}

void PcStation::begin_cycle() {
  if (!program_) return;
  req_len_ = program_->first_request(req_, sizeof req_);
  if (req_len_ == 0) return;
  busy_ = true;
  send_request();
}

void PcStation::send_request() {
  rsp_.clear();  // libmodbus flushes the input before a request
  awaiting_ = true;
  ++txn_;
  ++counters_.transactions;
  size_t gap_index = 0;
  SimNs gap_ns = 0;
  if (req_len_ > 1 && rng_.chance_ppm(timing_.split_ppm)) {
    gap_index = static_cast<size_t>(rng_.range(1, req_len_ - 1u));
    gap_ns = rng_.range(timing_.split_gap_min_ns, timing_.split_gap_max_ns);
    ++counters_.splits;
  }
  tx_.send(req_, req_len_, gap_index, gap_ns);
  q_.at(tx_.free_at() + timing_.timeout_ns, this, kTimeout, (uint64_t{txn_} << 32) | generation_);
}

uint16_t PcStation::expected_length() const {
  if (rsp_.size() < 2) return 0;
  const uint8_t fc = rsp_[1];
  if (fc & 0x80) return 5;
  switch (fc) {
    case modbus::fc::kReadCoils:
    case modbus::fc::kReadDiscreteInputs:
    case modbus::fc::kReadHoldingRegisters:
    case modbus::fc::kReadInputRegisters:
    case modbus::fc::kReadWriteMultipleRegisters:
      return rsp_.size() < 3 ? 0 : static_cast<uint16_t>(5u + rsp_[2]);
    default:
      return 8;  // 05 06 0F 10 08: fixed 8 bytes
  }
}

void PcStation::attach_serial(UartChannel* rx) {
  rx_ = rx;
  rx->on_sent = [this] {
    SerialChar c;
    while (rx_->take(q_.now(), &c)) on_byte(c.byte);
  };
}

void PcStation::on_byte(uint8_t byte) {
  if (!awaiting_) return;  // nobody listens: dropped like a flushed buffer
  rsp_.push_back(byte);
  const uint16_t want = expected_length();
  if ((want != 0 && rsp_.size() >= want) || rsp_.size() >= 256) complete(false);
}

void PcStation::complete(bool timed_out) {
  awaiting_ = false;
  modbus::Response r;
  modbus::ParseStatus status = modbus::ParseStatus::kTooShort;
  if (!timed_out) {
    status = modbus::parse_response(req_, req_len_, rsp_.data(), static_cast<uint16_t>(rsp_.size()), r);
  }
  const bool ok = status == modbus::ParseStatus::kOk;
  if (!ok) ++counters_.failures;
  if (on_transaction) on_transaction(index_, req_, req_len_, ok, status);
  req_len_ = program_->on_response(ok ? &r : nullptr, req_, sizeof req_);
  if (req_len_ != 0) {
    if (timing_.compute_ns != 0)
      q_.at(q_.now() + timing_.compute_ns, this, kSend, generation_);
    else
      send_request();
    return;
  }
  busy_ = false;
  if (start_when_free_) {
    start_when_free_ = false;
    begin_cycle();
  }
}

}  // namespace sim
}  // namespace mb2co
