// canopen::ParamStorage on the ATmega328P's 1 KiB EEPROM (1010h save, 1011h
// restore, 2000h node id / bit rate / Modbus address at start-up). The core
// owns the layout (two slots, docs in param_storage.cpp). Writes use
// eeprom_update_block: only bytes that differ are programmed (3.3 ms each).
// A save writes one byte per call and only when eeprom_storage_ready(): the
// byte before it is programmed (EEPE clear), so no write waits and the main
// loop keeps running during the ~1.5 s of a whole slot.
#pragma once
#include "canopen/param_storage.h"

namespace mb2co {
namespace avr {

/// Bytes of EEPROM the storage may use (the whole part).
constexpr uint16_t kEepromBytes = 1024;

bool eeprom_storage_read(void* ctx, uint16_t offset, uint8_t* data, uint16_t len);
bool eeprom_storage_write(void* ctx, uint16_t offset, const uint8_t* data, uint16_t len);
/// No EEPROM byte being programmed (EECR.EEPE clear).
bool eeprom_storage_ready(void* ctx);

/// Reads and writes beyond kEepromBytes fail (a save then reports failure).
/// constexpr: a global built from it is initialised data, not constructor
/// code (smaller on the Uno: docs/performance.md).
constexpr canopen::ParamStorage eeprom_storage() {
  return canopen::ParamStorage{&eeprom_storage_read, &eeprom_storage_write, nullptr, nullptr,
                               &eeprom_storage_ready};
}

}  // namespace avr
}  // namespace mb2co
