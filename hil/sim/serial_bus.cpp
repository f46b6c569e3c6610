#include "sim/serial_bus.h"

#include <algorithm>

#include "serialnet/connection_set.h"

namespace mb2co {
namespace sim {
namespace {

bool after(uint32_t a, uint32_t b) {
  return static_cast<int32_t>(a - b) > 0;
}

}  // namespace

SerialBus::SerialBus(const serialnet::ConnectionSet& set, uint32_t baud)
    : set_(set), byte_us_(serialnet::byte_time_us(baud)) {}

modbus::ByteSink SerialBus::port(int index) {
  ports_.push_back(Port{this, index});
  return modbus::ByteSink{&SerialBus::write, &ports_.back()};
}

void SerialBus::attach(int index, BusDevice* device) {
  if (devices_.size() <= static_cast<size_t>(index))
    devices_.resize(static_cast<size_t>(index) + 1u, nullptr);
  devices_[static_cast<size_t>(index)] = device;
}

void SerialBus::detach(int index) {
  devices_[static_cast<size_t>(index)] = nullptr;
}

void SerialBus::inject(int talker, const std::vector<uint8_t>& bytes) {
  transmit(talker, bytes.data(), static_cast<uint8_t>(bytes.size()));
}

void SerialBus::run_until(uint32_t until_us) {
  for (;;) {
    NextDeadline d(now);
    for (BusDevice* dev : devices_) {
      if (dev != nullptr) dev->next_deadline(d);
    }
    if (!bytes_.empty()) d.at(bytes_.front().at_us);
    uint32_t at = until_us;
    if (!d.result(&at)) at = until_us;
    if (at == now && processed_at_now_) at = now + kRetryStepUs;
    if (time_reached(at, until_us)) at = until_us;
    if (at != now) processed_at_now_ = false;
    now = at;
    deliver_due();
    for (BusDevice* dev : devices_) {
      if (dev != nullptr) dev->process(now);
    }
    processed_at_now_ = true;
    if (now == until_us) return;
  }
}

bool SerialBus::write(void* ctx, const uint8_t* data, uint16_t length) {
  Port& p = *static_cast<Port*>(ctx);
  if (p.bus->devices_[static_cast<size_t>(p.index)] == nullptr) return true;  // unplugged: into the void
  p.bus->transmit(p.index, data, static_cast<uint8_t>(length));
  return true;
}

void SerialBus::prune_on_line() {
  on_line_.erase(std::remove_if(on_line_.begin(), on_line_.end(),
                                [this](size_t i) { return !after(log[i].end_us + byte_us_, now); }),
                 on_line_.end());
}

void SerialBus::transmit(int talker, const uint8_t* data, uint8_t n) {
  // A talker's own bytes follow each other (its UART); others may overlap.
  uint32_t start = now;
  for (const Byte& b : bytes_) {
    if (b.talker == talker && after(b.at_us, start)) start = b.at_us;
  }
  Sent s;
  s.talker = talker;
  s.start_us = start;
  s.end_us = start + n * byte_us_;
  serialnet::Decoder dec(set_);
  s.msg = {};
  s.can_id = 0xFFFF;
  for (uint8_t i = 0; i < n; ++i) {
    if (dec.push(data[i], start + (i + 1u) * byte_us_) == serialnet::Decoder::kMessage) s.msg = dec.message();
  }
  serialnet::serial_to_can(set_, s.msg.id, &s.can_id);
  prune_on_line();
  for (size_t i : on_line_) {
    Sent& other = log[i];
    if (other.talker != talker && after(other.end_us, s.start_us) && after(s.end_us, other.start_us)) {
      if (!other.collided) ++collisions;
      other.collided = true;
      s.collided = true;
    }
  }
  log.push_back(s);
  on_line_.push_back(log.size() - 1u);
  if (on_sent) on_sent(s);
  for (uint8_t i = 0; i < n; ++i) {
    bytes_.push_back(Byte{start + (i + 1u) * byte_us_, data[i], talker, log.size() - 1u});
  }
  std::stable_sort(bytes_.begin(), bytes_.end(),
                   [](const Byte& a, const Byte& b) { return static_cast<int32_t>(a.at_us - b.at_us) < 0; });
}

void SerialBus::deliver_due() {
  while (!bytes_.empty() && time_reached(now, bytes_.front().at_us)) {
    const Byte b = bytes_.front();
    bytes_.pop_front();
    uint8_t value = b.value;
    if (log[b.sent].collided && overlaps_other(b)) value = static_cast<uint8_t>(value ^ 0xA5u);
    for (size_t i = 0; i < devices_.size(); ++i) {
      if (devices_[i] != nullptr && static_cast<int>(i) != b.talker) devices_[i]->on_byte(value, b.at_us);
    }
  }
}

bool SerialBus::overlaps_other(const Byte& b) const {
  const uint32_t from = b.at_us - byte_us_;
  for (size_t i : on_line_) {
    const Sent& s = log[i];
    if (s.talker != b.talker && after(s.end_us, from) && after(b.at_us, s.start_us)) return true;
  }
  return false;
}

}  // namespace sim
}  // namespace mb2co
