// Test harness: N gateways on an in-process CAN bus (every frame reaches every
// other station at the same instant; a filter can drop frames) and a Modbus
// master per station that talks to the gateway's slave byte by byte at
// 115200 baud, in virtual time.
#pragma once
#include <stdint.h>

#include <algorithm>
#include <deque>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "gateway/gateway.h"
#include "modbus/master_codec.h"

namespace mb2co {
namespace test {

class Line {
 public:
  static constexpr uint32_t kBaud = 115200;
  static constexpr uint32_t kCharUs = 96;  // 11 bits at 115200 baud, rounded up

  struct Station {
    std::unique_ptr<gateway::Gateway> gw;
    std::vector<uint8_t> eeprom = std::vector<uint8_t>(1024, 0xFF);
    canopen::ParamStorage storage;
    std::vector<uint8_t> serial_out;
    uint8_t buttons = 0;
    uint8_t leds = 0;
    bool powered = true;
  };

  /// Commissions each station like a technician would: power on with
  /// defaults and node id i+1, `configure` its OD (over SDO semantics), save
  /// (1010h) into its EEPROM, then every station powers on together.
  explicit Line(int n, std::function<void(canopen::ObjectDictionary&, int)> configure = nullptr) {
    stations_.resize(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
      Station& s = stations_[static_cast<size_t>(i)];
      s.storage = canopen::ParamStorage{&Line::eeprom_read, &Line::eeprom_write, nullptr, &s, nullptr};
      gateway::GatewayPorts ports{CanSink{&Line::can_send, this}, modbus::ByteSink{&Line::serial_send, &s},
                                  &s.storage, kBaud};
      s.gw.reset(new gateway::Gateway(ports));
      current_ = i;
      commissioning_ = true;
      s.gw->start(now_us, static_cast<uint8_t>(i + 1));
      if (configure) configure(s.gw->od(), i);
      uint8_t save[4];
      canopen::put_le32(save, canopen::kSaveSignature);
      if (s.gw->od().write(0x1010, 1, save, 4) != canopen::kSdoOk) throw std::runtime_error("save failed");
      while (s.gw->node().saving()) s.gw->process(now_us, 0);  // the save's passes
      commissioning_ = false;
    }
    for (int i = 0; i < n; ++i) power_on(i);
    deliver();
  }

  /// Power-on of station i with what its EEPROM holds.
  void power_on(int i) {
    Station& s = stations_[static_cast<size_t>(i)];
    s.powered = true;
    current_ = i;
    s.gw->start(now_us, 1);
  }

  gateway::Gateway& gw(int i) { return *stations_[static_cast<size_t>(i)].gw; }
  Station& station(int i) { return stations_[static_cast<size_t>(i)]; }
  uint32_t od_get(int i, uint16_t index, uint8_t sub) {
    canopen::ObjectDictionary& od = gw(i).od();
    return od.get(od.find(index, sub));
  }

  /// Advances virtual time by `us` in steps of `step_us` (the firmware loop).
  void run_us(uint32_t us, uint32_t step_us = 500) {
    for (uint32_t t = 0; t < us; t += step_us) {
      now_us += step_us;
      for (size_t i = 0; i < stations_.size(); ++i) {
        Station& s = stations_[i];
        if (!s.powered) continue;
        current_ = static_cast<int>(i);
        s.leds = s.gw->process(now_us, s.buttons);
      }
      deliver();
    }
  }
  void run_ms(uint32_t ms) { run_us(ms * 1000u); }

  /// Sends a Modbus request to station i and returns the raw response (empty
  /// when the slave stays silent within `timeout_us`).
  std::vector<uint8_t> modbus(int i, const uint8_t* req, uint16_t len, uint32_t timeout_us = 20000) {
    Station& s = stations_[static_cast<size_t>(i)];
    s.serial_out.clear();
    for (uint16_t k = 0; k < len; ++k) {
      now_us += kCharUs;
      s.gw->on_serial_byte(req[k], now_us);
    }
    for (uint32_t waited = 0; waited < timeout_us && s.serial_out.empty(); waited += 100) run_us(100, 100);
    run_us(2000, 100);  // let the whole response out
    return s.serial_out;
  }

  /// Frames on the bus so far (id, sender index).
  struct Sent {
    CanFrame frame;
    int from;
    uint32_t at_us;
  };
  std::vector<Sent> log;
  /// Return false to drop a frame (it never reaches the other stations).
  std::function<bool(const CanFrame&, int from)> filter;
  uint32_t now_us = 0;

 private:
  static bool eeprom_read(void* ctx, uint16_t at, uint8_t* data, uint16_t n) {
    Station& s = *static_cast<Station*>(ctx);
    if (at + n > s.eeprom.size()) return false;
    std::copy(s.eeprom.begin() + at, s.eeprom.begin() + at + n, data);
    return true;
  }
  static bool eeprom_write(void* ctx, uint16_t at, const uint8_t* data, uint16_t n) {
    Station& s = *static_cast<Station*>(ctx);
    if (at + n > s.eeprom.size()) return false;
    std::copy(data, data + n, s.eeprom.begin() + at);
    return true;
  }
  static bool can_send(void* ctx, const CanFrame& f) {
    Line& l = *static_cast<Line*>(ctx);
    if (l.commissioning_) return true;  // alone on the bench: nobody listens
    l.log.push_back({f, l.current_, l.now_us});
    if (!l.filter || l.filter(f, l.current_)) l.queue_.push_back({f, l.current_, l.now_us});
    return true;
  }
  static bool serial_send(void* ctx, const uint8_t* data, uint16_t n) {
    Station& s = *static_cast<Station*>(ctx);
    s.serial_out.insert(s.serial_out.end(), data, data + n);
    return true;
  }
  void deliver() {
    while (!queue_.empty()) {
      const Sent m = queue_.front();
      queue_.pop_front();
      for (size_t i = 0; i < stations_.size(); ++i) {
        if (static_cast<int>(i) == m.from || !stations_[i].powered) continue;
        current_ = static_cast<int>(i);
        stations_[i].gw->on_can_frame(m.frame, now_us);
      }
    }
  }

  std::vector<Station> stations_;
  bool commissioning_ = false;
  std::deque<Sent> queue_;
  int current_ = 0;
};

}  // namespace test
}  // namespace mb2co
