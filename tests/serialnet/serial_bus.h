// A virtual multi-drop serial line in virtual time, for the serialnet tests:
// one talker at a time, every byte delivered to every other device when its
// last bit has arrived (10 bits per byte at the baud rate), and two talkers
// whose bytes overlap corrupt each other (both messages are lost, as on
// RS-485). A log of every message written, decoded by the bus itself, with
// its talker and time on the line, for checking who talked when.
#pragma once
#include <stdint.h>

#include <algorithm>
#include <deque>
#include <functional>
#include <vector>

#include "canopen/clock.h"
#include "canopen/sdo_client.h"
#include "ionode/io_node.h"
#include "platform/device_port.h"
#include "serialnet/frame_codec.h"
#include "serialnet/serial_link.h"
#include "serialnet/serial_node.h"

namespace mb2co {
namespace test {

/// One device on the line, as the bus drives it.
class BusDevice {
 public:
  virtual ~BusDevice() = default;
  virtual void on_byte(uint8_t byte, uint32_t byte_us) = 0;
  virtual void process(uint32_t now_us) = 0;
  virtual void next_deadline(NextDeadline& d) const = 0;
};

class SerialBus {
 public:
  /// One message as written to the line.
  struct Sent {
    int talker;
    uint32_t start_us, end_us;
    serialnet::SerialMessage msg;  ///< decoded from the written bytes
    uint16_t can_id;               ///< serial_to_can of msg.id
    bool collided = false;         ///< overlapped another talker's bytes
  };

  SerialBus(const serialnet::ConnectionSet& set, uint32_t baud)
      : set_(set), byte_us_(serialnet::byte_time_us(baud)) {}

  uint32_t now = 0;
  std::vector<Sent> log;
  int collisions = 0;

  /// A sink for talker `index` (stable: ports live in a deque).
  modbus::ByteSink port(int index) {
    ports_.push_back(Port{this, index});
    return modbus::ByteSink{&SerialBus::write, &ports_.back()};
  }
  /// Device `index` (the index its port() was made with) joins the line.
  void attach(int index, BusDevice* device) {
    if (devices_.size() <= static_cast<size_t>(index))
      devices_.resize(static_cast<size_t>(index) + 1u, nullptr);
    devices_[static_cast<size_t>(index)] = device;
  }
  /// The device is unplugged: it neither runs, hears nor talks from now on.
  void detach(int index) { devices_[static_cast<size_t>(index)] = nullptr; }

  /// Raw bytes from `talker` at now (a device talking out of turn).
  void inject(int talker, const std::vector<uint8_t>& bytes) {
    transmit(talker, bytes.data(), static_cast<uint8_t>(bytes.size()));
  }

  /// Runs every device and the line until `until_us` (virtual time): from
  /// event to event (a byte's last bit, a device's deadline), never past it.
  void run_until(uint32_t until_us) {
    for (;;) {
      NextDeadline d(now);
      for (BusDevice* dev : devices_) {
        if (dev != nullptr) dev->next_deadline(d);
      }
      if (!bytes_.empty()) d.at(bytes_.front().at_us);
      uint32_t at = until_us;
      if (!d.result(&at)) at = until_us;
      if (at == now && processed_at_now_) at = now + kRetryStepUs;  // a device retries: let time pass
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
  void run_for(uint32_t us) { run_until(now + us); }

  uint32_t byte_us() const { return byte_us_; }

 private:
  static const uint32_t kRetryStepUs = 20;
  struct Port {
    SerialBus* bus;
    int index;
  };
  struct Byte {
    uint32_t at_us;  ///< its last bit
    uint8_t value;
    int talker;
    size_t sent;  ///< index into log
  };

  static bool write(void* ctx, const uint8_t* data, uint16_t length) {
    Port& p = *static_cast<Port*>(ctx);
    if (p.bus->devices_[static_cast<size_t>(p.index)] == nullptr) return true;  // unplugged: into the void
    p.bus->transmit(p.index, data, static_cast<uint8_t>(length));
    return true;
  }

  void transmit(int talker, const uint8_t* data, uint8_t n) {
    // A talker's own bytes follow each other (its UART); others may overlap.
    uint32_t start = now;
    for (const Byte& b : bytes_) {
      if (b.talker == talker && static_cast<int32_t>(b.at_us - start) > 0) start = b.at_us;
    }
    Sent s;
    s.talker = talker;
    s.start_us = start;
    s.end_us = start + n * byte_us_;
    serialnet::Decoder dec(set_);
    s.msg = {};
    s.can_id = 0xFFFF;
    for (uint8_t i = 0; i < n; ++i) {
      if (dec.push(data[i], start + (i + 1u) * byte_us_) == serialnet::Decoder::kMessage)
        s.msg = dec.message();
    }
    serialnet::serial_to_can(set_, s.msg.id, &s.can_id);
    for (Sent& other : log) {
      if (other.talker != talker && static_cast<int32_t>(other.end_us - s.start_us) > 0 &&
          static_cast<int32_t>(s.end_us - other.start_us) > 0) {
        if (!other.collided) ++collisions;
        other.collided = true;
        s.collided = true;
      }
    }
    log.push_back(s);
    for (uint8_t i = 0; i < n; ++i) {
      bytes_.push_back(Byte{start + (i + 1u) * byte_us_, data[i], talker, log.size() - 1u});
    }
    std::stable_sort(bytes_.begin(), bytes_.end(), [](const Byte& a, const Byte& b) {
      return static_cast<int32_t>(a.at_us - b.at_us) < 0;
    });
  }

  // Bytes whose slot overlaps another talker's message arrive as garbage.
  void deliver_due() {
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
  bool overlaps_other(const Byte& b) const {
    const uint32_t from = b.at_us - byte_us_;
    for (const Sent& s : log) {
      if (s.talker != b.talker && static_cast<int32_t>(s.end_us - from) > 0 &&
          static_cast<int32_t>(b.at_us - s.start_us) > 0) {
        return true;
      }
    }
    return false;
  }

  serialnet::ConnectionSet set_;
  uint32_t byte_us_;
  std::deque<Port> ports_;
  std::vector<BusDevice*> devices_;
  std::deque<Byte> bytes_;
  bool processed_at_now_ = false;
};

/// An I/O node (shared/ionode, the real node core) on the line through a
/// SerialLink, optionally with an SDO client sharing its link (a master).
class Station : public BusDevice {
 public:
  Station(SerialBus& bus, int index, const serialnet::BusConfig& config, uint8_t node_id)
      : link(config, node_id, bus.port(index)), io(link.can_sink()) {
    link.set_receiver(serialnet::CanReceiver{&Station::receive, this});
    bus.attach(index, this);
  }

  serialnet::SerialLink link;
  ionode::IoNode io;
  canopen::SdoClient client{};
  bool client_on = false;
  std::vector<std::pair<uint32_t, CanFrame>> received;  ///< every frame handed to the node

  canopen::Node& node() { return io.node(); }

  void on_byte(uint8_t byte, uint32_t byte_us) override { link.on_byte(byte, byte_us); }
  void process(uint32_t now_us) override {
    io.process(now_us);
    if (client_on) client.process(now_us, link.can_sink());
    link.process(now_us);
  }
  void next_deadline(NextDeadline& d) const override {
    io_node().next_deadline(d);
    if (client_on) client.next_deadline(d);
    link.next_deadline(d);
  }

 private:
  const canopen::Node& io_node() const { return const_cast<Station*>(this)->io.node(); }
  static void receive(void* ctx, const CanFrame& f, uint32_t now_us) {
    Station& s = *static_cast<Station*>(ctx);
    s.received.emplace_back(now_us, f);
    s.io.receive(f, now_us);
    if (s.client_on) s.client.on_frame(f, now_us, s.link.can_sink());
  }
};

}  // namespace test
}  // namespace mb2co
