// A RAM-backed ParamStorage for the tests of saved parameters (1010h), with
// the failures and the busy time of an EEPROM on demand.
#pragma once
#include <stdint.h>
#include <string.h>

#include <vector>

#include "canopen/clock.h"
#include "platform/device_port.h"

namespace mb2co {
namespace test {

/// Byte-addressed storage in RAM; can be told to fail from the n-th write on,
/// and to take `busy_us` of virtual time (*clock) per byte written as an
/// EEPROM does (ParamStorage::ready false meanwhile).
struct RamStorage {
  std::vector<uint8_t> mem = std::vector<uint8_t>(1024, 0xFF);
  int writes_left = -1;  ///< -1: never fail
  const uint32_t* clock = nullptr;
  uint32_t busy_us = 0;
  uint32_t ready_at = 0;
  int early_writes = 0;  ///< writes while not ready (a port would block)
  static bool ready(void* ctx) {
    const RamStorage& s = *static_cast<RamStorage*>(ctx);
    return s.clock == nullptr || time_reached(*s.clock, s.ready_at);
  }
  static bool read(void* ctx, uint16_t at, uint8_t* data, uint16_t len) {
    RamStorage& s = *static_cast<RamStorage*>(ctx);
    if (static_cast<size_t>(at) + len > s.mem.size()) return false;
    memcpy(data, &s.mem[at], len);
    return true;
  }
  static bool write(void* ctx, uint16_t at, const uint8_t* data, uint16_t len) {
    RamStorage& s = *static_cast<RamStorage*>(ctx);
    if (s.writes_left == 0 || static_cast<size_t>(at) + len > s.mem.size()) return false;
    if (s.writes_left > 0) --s.writes_left;
    if (!ready(ctx)) ++s.early_writes;
    memcpy(&s.mem[at], data, len);
    if (s.clock != nullptr) s.ready_at = *s.clock + s.busy_us * len;
    return true;
  }
  canopen::ParamStorage api() {
    return canopen::ParamStorage{&RamStorage::read, &RamStorage::write, nullptr, this, &RamStorage::ready};
  }
};

}  // namespace test
}  // namespace mb2co
