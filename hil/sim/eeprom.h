// A station's EEPROM in virtual time: 1 KiB, erased (FF) at the start,
// kept across power cycles; the Gateway sees it as canopen::ParamStorage.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <algorithm>
#include <vector>

#include "platform/device_port.h"

namespace mb2co {
namespace sim {

class Eeprom {
 public:
  Eeprom() : bytes_(1024, 0xFF), storage_{&Eeprom::read, &Eeprom::write, nullptr, this} {}
  Eeprom(const Eeprom&) = delete;  // storage_ points at this object
  Eeprom& operator=(const Eeprom&) = delete;

  const canopen::ParamStorage& storage() const { return storage_; }

 private:
  static bool read(void* ctx, uint16_t at, uint8_t* data, uint16_t len) {
    Eeprom& e = *static_cast<Eeprom*>(ctx);
    if (size_t{at} + len > e.bytes_.size()) return false;
    std::copy(e.bytes_.begin() + at, e.bytes_.begin() + at + len, data);
    return true;
  }
  static bool write(void* ctx, uint16_t at, const uint8_t* data, uint16_t len) {
    Eeprom& e = *static_cast<Eeprom*>(ctx);
    if (size_t{at} + len > e.bytes_.size()) return false;
    std::copy(data, data + len, e.bytes_.begin() + at);
    return true;
  }

  std::vector<uint8_t> bytes_;
  canopen::ParamStorage storage_;
};

}  // namespace sim
}  // namespace mb2co
