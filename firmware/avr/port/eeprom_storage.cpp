#include "port/eeprom_storage.h"

#include <avr/eeprom.h>

namespace mb2co {
namespace avr {
namespace {

static_assert(kEepromBytes == E2END + 1, "ATmega328P EEPROM size");

bool fits(uint16_t offset, uint16_t len) {
  return offset <= kEepromBytes && len <= kEepromBytes - offset;
}

// EEPROM addresses are pointers in avr-libc's API.
void* address(uint16_t offset) {
  return reinterpret_cast<void*>(static_cast<uintptr_t>(offset));
}

}  // namespace

bool eeprom_storage_read(void*, uint16_t offset, uint8_t* data, uint16_t len) {
  if (!fits(offset, len)) return false;
  eeprom_read_block(data, address(offset), len);
  return true;
}

bool eeprom_storage_write(void*, uint16_t offset, const uint8_t* data, uint16_t len) {
  if (!fits(offset, len)) return false;
  eeprom_update_block(data, address(offset), len);
  return true;
}

bool eeprom_storage_ready(void*) {
  return eeprom_is_ready();
}

}  // namespace avr
}  // namespace mb2co
