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

/// Reads and writes beyond kEepromBytes fail (a save then reports failure).
canopen::ParamStorage eeprom_storage();

}  // namespace avr
}  // namespace mb2co
