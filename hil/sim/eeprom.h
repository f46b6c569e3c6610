// A station's EEPROM in virtual time: 1 KiB, erased (FF) at the start,
// kept across power cycles; the Gateway sees it as canopen::ParamStorage.
// Programming a byte takes kByteNs, as on the ATmega328P (datasheet: 3.3 ms):
// ParamStorage::ready is false meanwhile, so a save (1010h) runs over the
// passes of that time (canopen::ParamSave). The station tells the time
// (set_now) before each call into the firmware.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <algorithm>
#include <vector>

#include "platform/device_port.h"
#include "sim/event_queue.h"

namespace mb2co {
namespace sim {

class Eeprom {
 public:
  /// Programming time of one byte (ATmega328P: 3.3 ms, EEPE set meanwhile).
  static constexpr SimNs kByteNs = 3300 * kNsPerUs;

  Eeprom() : bytes_(1024, 0xFF), storage_{&Eeprom::read, &Eeprom::write, nullptr, this, &Eeprom::ready} {}
  Eeprom(const Eeprom&) = delete;  // storage_ points at this object
  Eeprom& operator=(const Eeprom&) = delete;

  const canopen::ParamStorage& storage() const { return storage_; }
  /// Simulated time of the firmware's next calls.
  void set_now(SimNs t) { now_ = t; }
  /// Every byte programmed, the clock back at 0 (the bench's time before
  /// the line's: NodeStation::commission).
  void settle() { now_ = ready_at_ = 0; }
  /// When the byte being programmed is done (ParamStorage::ready from then
  /// on): the only input that changes while a save waits for the EEPROM.
  SimNs ready_at() const { return ready_at_; }
  /// Bytes programmed so far (all power cycles).
  uint64_t bytes_written() const { return written_; }

 private:
  static bool ready(void* ctx) {
    const Eeprom& e = *static_cast<Eeprom*>(ctx);
    return e.now_ >= e.ready_at_;
  }
  static bool read(void* ctx, uint16_t at, uint8_t* data, uint16_t len) {
    Eeprom& e = *static_cast<Eeprom*>(ctx);
    if (size_t{at} + len > e.bytes_.size()) return false;
    std::copy(e.bytes_.begin() + at, e.bytes_.begin() + at + len, data);
    return true;
  }
  /// Programs the bytes one after the other from now (or from the end of
  /// the byte still being programmed: the AVR's eeprom_write waits for it).
  static bool write(void* ctx, uint16_t at, const uint8_t* data, uint16_t len) {
    Eeprom& e = *static_cast<Eeprom*>(ctx);
    if (size_t{at} + len > e.bytes_.size()) return false;
    std::copy(data, data + len, e.bytes_.begin() + at);
    e.ready_at_ = std::max(e.now_, e.ready_at_) + kByteNs * len;
    e.written_ += len;
    return true;
  }

  std::vector<uint8_t> bytes_;
  canopen::ParamStorage storage_;
  SimNs now_ = 0;
  SimNs ready_at_ = 0;
  uint64_t written_ = 0;
};

}  // namespace sim
}  // namespace mb2co
