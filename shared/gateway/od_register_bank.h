// Modbus tables as windows onto the Object Dictionary. Each table has a map in
// the OD (2400h holding registers, 2401h input registers, 2402h coils, 2403h
// discrete inputs) of 32-bit entries in the PDO mapping format (index, sub,
// length in bits). Entries are laid out back to back from address 0: an entry
// takes one register per 16 bits, high word first (up to 16 bits one, 24 and
// 32 bits two; in host builds, MB2CO_CONFIG_WIDE_TYPES, 40 and 48 bits three, 56
// and 64 bits four, and a VISIBLE_STRING or OCTET_STRING of n bytes a run of
// (n + 1) / 2 registers, two characters each, the first in the high byte);
// a coil or discrete input is one bit (bit 0 of an 8-bit entry); an entry 0
// is an unmapped address. A value of several registers is written only
// whole, in one request. OD access rights hold: a write to an entry that is not
// writable is exception 02 (decided before anything is executed), a value the
// entry refuses (limits, write hooks) is exception 04 and nothing is changed.
#pragma once
#include <stdint.h>
#include <string.h>

#include "canopen/od.h"
#include "gateway/gateway_od.h"
#include "gateway/register_map.h"
#include "modbus/register_bank.h"

namespace mb2co {
namespace gateway {

class OdRegisterBank : public modbus::RegisterBank {
 public:
  /// Binds itself as the owner of the maps' handler (kOwnerRegisterBank):
  /// every write of 2400h-2403h, by SDO or Modbus, is checked by the bank.
  explicit OdRegisterBank(canopen::ObjectDictionary& od) : od_(od) {
    memset(cached_rows_, 0xFF, sizeof cached_rows_);
    od_.set_owner(kOwnerRegisterBank, this);
  }

  bool covers(modbus::Table table, modbus::Access access, uint16_t start, uint16_t count) override;
  modbus::Exception read_bits(modbus::Table table, uint16_t start, modbus::BitSpan out) override;
  modbus::Exception read_registers(modbus::Table table, uint16_t start, modbus::RegisterSpan out) override;
  modbus::Exception write_coils(uint16_t start, modbus::ConstBitSpan values) override;
  modbus::Exception write_registers(uint16_t start, modbus::ConstRegisterSpan values) override;

  /// OD index of a table's map (register_map.h).
  static uint16_t map_index(modbus::Table table) { return gateway::map_index(table); }
  /// Validates a write of `data` to map `index` (2400h-2403h) sub `sub`
  /// (the maps' handler, GatewayHandlers::register_map):
  /// the count within the map's capacity, an entry that names an existing
  /// numeric entry the table can carry. SDO abort code or 0.
  canopen::SdoAbort check_map_write(uint16_t index, uint8_t sub, const uint8_t* data) const;
  /// Bytes of the longest register run (a string of 15 registers, rounded).
  static const uint8_t kRunBytes = 32;

 private:
  /// One mapped item: OD row, the entry it maps (index, sub, length in bits),
  /// first address, width in addresses.
  struct Item {
    uint16_t row;    ///< kNoRow for an unmapped address
    uint16_t index;  ///< index and sub of `row`, as the map entry names them
    uint8_t sub;     ///< (no flash reads for them)
    uint8_t bits;
    uint8_t width;
    uint16_t first;
  };
  /// A walk over one table's map in address order. A request reaches its
  /// addresses in ascending order, so it costs one pass over the map whatever
  /// its length, and an OD lookup only for the items it uses.
  struct Walk {
    Item item;           ///< the current item (valid once reach() returned true)
    uint16_t row0;       ///< row of the map's sub 0
    uint8_t count;       ///< entries in use (sub 0)
    uint8_t sub;         ///< sub-index of `item`, 0 before the first
    bool bit_table;      ///< coils, discrete inputs: every item is one address
    uint8_t cache_base;  ///< this table's first slot in cached_rows_
    uint8_t cache_size;  ///< its slots (the map's capacity)
  };
  void begin(modbus::Table table, Walk* walk) const;
  /// Moves on to the item holding `address` (not before the current one);
  /// false when the map ends before it.
  bool reach(Walk* walk, uint16_t address);
  /// Row of the current item's entry (kNoRow for an unmapped address).
  uint16_t row_of(const Walk& walk, uint32_t entry);
  /// One item's value through the OD's write path (`apply`: see write_row).
  modbus::Exception write_value(const Item& item, uint32_t value, bool apply);
  /// What the OD's answer to a write is in Modbus.
  static modbus::Exception exception_of(canopen::SdoAbort r);
  // Register runs: used where the profile has the wide types (profile::kWideTypes).
  /// True for an item wider than 32 bits or a string (a register run).
  bool is_run(const Item& item) const;
  /// Register `k` (0: the item's first address) of a register run.
  uint16_t run_register(const Item& item, uint16_t k) const;
  /// A register run's value from its registers (big-endian, 2 bytes each).
  modbus::Exception write_run(const Item& item, const uint8_t* registers, bool apply);
  /// One step of write_items(): check (`apply` false) or apply.
  modbus::Exception write_step(modbus::Table table, uint16_t start, uint16_t count, const uint8_t* bytes,
                               bool apply);
  modbus::Exception read_items(modbus::Table table, uint16_t start, uint16_t count, uint8_t* bytes);
  modbus::Exception write_items(modbus::Table table, uint16_t start, uint16_t count, const uint8_t* bytes);
  /// True when writing `row` changes the walk's items already laid out: the
  /// walk's own map at sub 0 (the count) up to the current item (rows of
  /// one index are contiguous). A later entry of that map is read when the
  /// walk reaches it; another table's map does not touch this walk.
  static bool moves_walk(const Walk& walk, uint16_t row) {
    return static_cast<uint16_t>(row - walk.row0) <= walk.sub;
  }

  canopen::ObjectDictionary& od_;
  /// The row each map entry named when it was last looked up, by table and
  /// sub-index (0xFF: none, or a row above 254), checked against the entry
  /// before use: a request's covers() and its read or write, and every later
  /// request, skip the OD's binary search.
  uint8_t cached_rows_[kCoilMapSize + kDiscreteMapSize + kInputMapSize + kHoldingMapSize];
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
