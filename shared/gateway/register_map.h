// Where an OD entry sits in the gateway's Modbus tables: the one piece of code
// that lays the register maps out, for the register bank (the firmware), the
// PC app, the OD tool's register-map page and the simulator.
//
// Each table has a map in the OD (2400h holding registers, 2401h input
// registers, 2402h coils, 2403h discrete inputs) of 32-bit entries in the PDO
// mapping format (index, sub, length in bits). Its items are laid out back to
// back from address 0, in sub-index order: in a register table an entry
// takes one register per 16 bits (at least one; on the AVR, whose maps hold
// nothing wider than 32 bits, at most two), in a bit table one address; an
// entry 0 is one unmapped address.
#pragma once
#include <stdint.h>

#include "canopen/od.h"
#include "canopen/pdo_map.h"
#include "gateway/gateway_od.h"
#include "modbus/register_bank.h"

namespace mb2co {
namespace gateway {

/// OD index of a table's map: 2400h holding, 2401h input registers, 2402h
/// coils, 2403h discrete inputs.
constexpr uint16_t map_index(modbus::Table table) {
  return static_cast<uint16_t>(0x2400 + (table == modbus::Table::kHoldingRegisters ? 0
                                         : table == modbus::Table::kInputRegisters ? 1
                                         : table == modbus::Table::kCoils          ? 2
                                                                                   : 3));
}
/// True for the indices of the maps (2400h-2403h).
constexpr bool is_map_index(uint16_t index) {
  return index >= 0x2400 && index <= 0x2403;
}
/// Coils and discrete inputs: every item is one bit (bit 0 of its entry).
constexpr bool is_bit_table(modbus::Table table) {
  return table == modbus::Table::kCoils || table == modbus::Table::kDiscreteInputs;
}
/// Sub-entries a table's map can hold (its sub 0 is at most this).
constexpr uint8_t map_capacity(modbus::Table table) {
  return table == modbus::Table::kHoldingRegisters ? kHoldingMapSize
         : table == modbus::Table::kInputRegisters ? kInputMapSize
         : table == modbus::Table::kCoils          ? kCoilMapSize
                                                   : kDiscreteMapSize;
}

/// Addresses one map entry takes (the layout rule above).
constexpr uint8_t entry_width(uint32_t entry, bool bit_table) {
  return (entry == 0 || bit_table || canopen::map_bits(entry) <= 16) ? 1
         : profile::kWideTypes ? static_cast<uint8_t>((canopen::map_bits(entry) + 15u) / 16u)
                               : 2;
}

/// True when map `entry` carries `key`'s value: its index and sub, and in a
/// register table all its bits (an entry mapped narrower is not its value).
constexpr bool entry_names(uint32_t entry, canopen::OdKey key, bool bit_table) {
  return entry != 0 && canopen::map_index(entry) == key.index && canopen::map_sub(entry) == key.sub &&
         (bit_table || canopen::map_bits(entry) == key.bits);
}

/// One item of a map: its sub-index, its entry, and the addresses
/// [first, first + width) it takes. width 0: not mapped (locate's answer).
struct MapItem {
  uint8_t sub;
  uint32_t entry;
  uint16_t first;
  uint8_t width;
  constexpr bool mapped() const { return width != 0; }
};

/// A walk over one map's items in address order. `Entries` tells the map's
/// entries: count() (sub 0) and entry(sub) for sub 1..count().
template <class Entries>
class MapWalk {
 public:
  constexpr MapWalk(const Entries& entries, bool bit_table)
      : entries_(entries), count_(entries.count()), bit_table_(bit_table), item_{0, 0, 0, 0} {}
  /// Moves on to the next item; false after the last.
  constexpr bool next() {
    if (item_.sub >= count_) return false;
    item_.first = static_cast<uint16_t>(item_.first + item_.width);
    ++item_.sub;
    item_.entry = entries_.entry(item_.sub);
    item_.width = entry_width(item_.entry, bit_table_);
    return true;
  }
  constexpr const MapItem& item() const { return item_; }

 private:
  Entries entries_;
  uint8_t count_;
  bool bit_table_;
  MapItem item_;
};

/// The first item of a map that carries `key` (entry_names), or one with
/// width 0.
template <class Entries>
constexpr MapItem locate_in(const Entries& entries, bool bit_table, canopen::OdKey key) {
  MapWalk<Entries> walk(entries, bit_table);
  while (walk.next()) {
    if (entry_names(walk.item().entry, key, bit_table)) return walk.item();
  }
  return MapItem{0, 0, 0xFFFF, 0};
}

/// A map as the OD holds it now (a count beyond the map's capacity is cut).
class OdMapEntries {
 public:
  OdMapEntries(const canopen::ObjectDictionary& od, modbus::Table table);
  uint8_t count() const { return count_; }
  uint32_t entry(uint8_t sub) const { return od_->get(static_cast<uint16_t>(row0_ + sub)); }

 private:
  const canopen::ObjectDictionary* od_;
  uint16_t row0_;
  uint8_t count_;
};

/// A map as the gateway OD's defaults lay it out (the firmware's default
/// map), at compile time.
class DefaultMapEntries {
 public:
  constexpr explicit DefaultMapEntries(modbus::Table table) : index_(map_index(table)) {}
  constexpr uint8_t count() const { return static_cast<uint8_t>(value(0)); }
  constexpr uint32_t entry(uint8_t sub) const { return value(sub); }

 private:
  constexpr uint32_t value(uint8_t sub) const {
    for (const canopen::OdDefault& d : od::GatewayDefaults) {
      if (d.index == index_ && d.sub == sub) return d.value;
    }
    return 0;
  }
  uint16_t index_;
};

/// Where `key` is in `table` of the OD's map now.
MapItem locate(const canopen::ObjectDictionary& od, modbus::Table table, canopen::OdKey key);

/// Where `key` is in `table` of the default map: for programs that talk to a
/// gateway with the default map and want its addresses as constants (the
/// simulator's PC programs, tests); a map that may have been changed is read
/// from the OD (locate).
constexpr MapItem default_location(modbus::Table table, canopen::OdKey key) {
  return locate_in(DefaultMapEntries(table), is_bit_table(table), key);
}
/// The address of default_location; 0xFFFF when the default map lacks `key`.
constexpr uint16_t default_address(modbus::Table table, canopen::OdKey key) {
  return default_location(table, key).first;
}

}  // namespace gateway
}  // namespace mb2co
