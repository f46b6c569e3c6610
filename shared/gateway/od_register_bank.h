// Modbus tables as windows onto the Object Dictionary. Each table has a map in
// the OD (2400h holding registers, 2401h input registers, 2402h coils, 2403h
// discrete inputs) of 32-bit entries in the PDO mapping format (index, sub,
// length in bits). Entries are laid out back to back from address 0: an entry
// of up to 16 bits is one register, a 32-bit entry two (high word first), a
// coil or discrete input is one bit (bit 0 of an 8-bit entry); an entry 0 is
// an unmapped address. OD access rights hold: a write to an entry that is not
// writable is exception 02 (decided before anything is executed), a value the
// entry refuses (limits, write hooks) is exception 04 and nothing is changed.
#pragma once
#include <stdint.h>

#include "canopen/od.h"
#include "modbus/register_bank.h"

namespace mb2co {
namespace gateway {

class OdRegisterBank : public modbus::RegisterBank {
 public:
  explicit OdRegisterBank(canopen::ObjectDictionary& od) : od_(od) {}

  bool covers(modbus::Table table, modbus::Access access, uint16_t start, uint16_t count) override;
  modbus::Exception read_bits(modbus::Table table, uint16_t start, modbus::BitSpan out) override;
  modbus::Exception read_registers(modbus::Table table, uint16_t start,
                                   modbus::RegisterSpan out) override;
  modbus::Exception write_coils(uint16_t start, modbus::ConstBitSpan values) override;
  modbus::Exception write_registers(uint16_t start, modbus::ConstRegisterSpan values) override;

  /// OD index of a table's map.
  static uint16_t map_index(modbus::Table table) {
    return static_cast<uint16_t>(0x2400 + static_cast<uint8_t>(table == modbus::Table::kHoldingRegisters ? 0
                                                                : table == modbus::Table::kInputRegisters ? 1
                                                                : table == modbus::Table::kCoils          ? 2
                                                                                                          : 3));
  }
  /// Validates a write to a map (2400h–2403h sub `sub`): SDO abort code or 0.
  static uint32_t check_map_write(const canopen::ObjectDictionary& od, uint16_t index, uint8_t sub,
                                  const uint8_t* data);

 private:
  /// One mapped item: OD row, length in bits, first address, width in addresses.
  struct Item {
    uint16_t row;    ///< kNoRow for an unmapped address
    uint8_t bits;
    uint8_t width;
    uint16_t first;
  };
  /// Finds the item holding `address` in `table`; false if beyond the map.
  bool locate(modbus::Table table, uint16_t address, Item* item) const;
  modbus::Exception write_value(const Item& item, uint32_t value);

  canopen::ObjectDictionary& od_;
};

/// FC 2B/0E basic objects from the OD: vendor name "mb2co", product code =
/// device name 1008h, revision = software version 100Ah.
class OdDeviceIdentity : public modbus::DeviceIdentity {
 public:
  explicit OdDeviceIdentity(const canopen::ObjectDictionary& od) : od_(od) {}
  uint8_t copy_object(uint8_t id, uint8_t* out, uint8_t capacity) override;

 private:
  const canopen::ObjectDictionary& od_;
};

}  // namespace gateway
}  // namespace mb2co
