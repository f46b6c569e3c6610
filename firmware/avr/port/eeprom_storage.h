// canopen::ParamStorage on the ATmega328P's 1 KiB EEPROM (1010h save, 1011h
// restore, 2000h node id / bit rate / Modbus address at start-up). The core
// owns the layout (magic, length, checksum from offset 0). Writes use
// eeprom_update_block: only bytes that differ are programmed (3.4 ms each,
// the main loop waits meanwhile; a full save of the gateway takes < 1.5 s).
#pragma once
#include "canopen/param_storage.h"

namespace mb2co {
namespace avr {

/// Bytes of EEPROM the storage may use (the whole part).
constexpr uint16_t kEepromBytes = 1024;

bool eeprom_storage_read(void* ctx, uint16_t offset, uint8_t* data, uint16_t len);
bool eeprom_storage_write(void* ctx, uint16_t offset, const uint8_t* data, uint16_t len);

/// Reads and writes beyond kEepromBytes fail (a save then reports failure).
/// constexpr: a global built from it is initialised data, not constructor
/// code (smaller on the Uno: docs/performance.md).
constexpr canopen::ParamStorage eeprom_storage() {
  return canopen::ParamStorage{&eeprom_storage_read, &eeprom_storage_write, nullptr, nullptr};
}

}  // namespace avr
}  // namespace mb2co
