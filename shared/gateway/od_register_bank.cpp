#include "gateway/od_register_bank.h"

#include <string.h>

#include "canopen/pdo_map.h"
#include "gateway/register_map.h"

namespace mb2co {
namespace gateway {

using canopen::ObjectDictionary;
using modbus::Exception;
using modbus::Table;

// Where each table's rows start in cached_rows_, and how many there are.
constexpr uint8_t kCacheBase[4] = {0, kCoilMapSize, kCoilMapSize + kDiscreteMapSize,
                                   kCoilMapSize + kDiscreteMapSize + kInputMapSize};
constexpr uint8_t kCacheSize[4] = {kCoilMapSize, kDiscreteMapSize, kInputMapSize, kHoldingMapSize};
static_assert(static_cast<uint8_t>(Table::kCoils) == 0 && static_cast<uint8_t>(Table::kDiscreteInputs) == 1 &&
                  static_cast<uint8_t>(Table::kInputRegisters) == 2 &&
                  static_cast<uint8_t>(Table::kHoldingRegisters) == 3,
              "cache layout by table");

void OdRegisterBank::begin(Table table, Walk* w) const {
  const uint8_t t = static_cast<uint8_t>(table);
  w->row0 = od_.find(map_index(table), 0);
  w->count = static_cast<uint8_t>(od_.get(w->row0));
  w->sub = 0;
  w->bit_table = is_bit_table(table);
  w->cache_base = kCacheBase[t];
  w->cache_size = kCacheSize[t];
  w->item.first = 0;
  w->item.width = 0;
}

uint16_t OdRegisterBank::row_of(const Walk& w, uint32_t entry) {
  if (entry == 0) return ObjectDictionary::kNoRow;
  const uint16_t index = canopen::map_index(entry);
  const uint8_t sub = canopen::map_sub(entry);
  uint8_t* slot = w.sub <= w.cache_size ? &cached_rows_[w.cache_base + w.sub - 1] : nullptr;
  // A remembered row is checked against the entry (two bytes of flash):
  // whoever changed the map, a stale row is never used.
  if (slot != nullptr && *slot != 0xFF && od_.index_of(*slot) == index && od_.sub_of(*slot) == sub) {
    return *slot;
  }
  const uint16_t row = od_.find(index, sub);
  if (slot != nullptr) *slot = static_cast<uint8_t>(row < 0xFF ? row : 0xFF);
  return row;
}

bool OdRegisterBank::reach(Walk* w, uint16_t address) {
  Item& it = w->item;
  if (w->sub != 0 && address < it.first + it.width) return true;
  uint32_t entry;
  do {
    if (w->sub >= w->count) return false;
    ++w->sub;
    entry = od_.get(static_cast<uint16_t>(w->row0 + w->sub));
    it.first = static_cast<uint16_t>(it.first + it.width);
    it.index = canopen::map_index(entry);
    it.sub = canopen::map_sub(entry);
    it.bits = canopen::map_bits(entry);
    // register_map.h lays the items out (on the AVR no entry is wider than
    // 32 bits: check_map_write).
    it.width = entry_width(entry, w->bit_table);
  } while (address >= it.first + it.width);
  // Only the item reached is looked up (not those before the request's start).
  it.row = row_of(*w, entry);
  return true;
}

bool OdRegisterBank::covers(Table table, modbus::Access access, uint16_t start, uint16_t count) {
  const uint32_t end = static_cast<uint32_t>(start) + count;
  Walk w;
  begin(table, &w);
  const Item& it = w.item;
  for (uint32_t a = start; a < end;) {
    if (!reach(&w, static_cast<uint16_t>(a)) || it.row == ObjectDictionary::kNoRow) return false;
    const uint8_t attr = od_.attr(it.row);
    // 32-bit like `end`: first + width stays below 41 (20 map entries), but a
    // 16-bit int sum widened is what check-int16.sh flags; one sum.
    const uint32_t item_end = static_cast<uint32_t>(it.first) + it.width;
    if (access == modbus::Access::kWrite) {
      if (!(attr & canopen::kAttrWrite)) return false;
      // A 32-bit value is written whole or not at all.
      if (it.first < start || item_end > end) return false;
    } else if (!(attr & canopen::kAttrRead)) {
      return false;
    }
    a = item_end;
  }
  return true;
}

Exception OdRegisterBank::read_bits(Table table, uint16_t start, modbus::BitSpan out) {
  return read_items(table, start, out.count, out.bytes);
}

Exception OdRegisterBank::read_registers(Table table, uint16_t start, modbus::RegisterSpan out) {
  return read_items(table, start, out.count, out.bytes);
}

// Bits and registers share one loop: a bit is bit 0 of its entry; a register
// the entry's low `bits` bits, or one half of a 32-bit entry (high first).
Exception OdRegisterBank::read_items(Table table, uint16_t start, uint16_t count, uint8_t* bytes) {
  Walk w;
  begin(table, &w);
  const Item& it = w.item;
  for (uint16_t i = 0; i < count; ++i) {
    const uint16_t a = static_cast<uint16_t>(start + i);
    if (!reach(&w, a)) return Exception::kIllegalDataAddress;
    if (profile::kWideTypes && is_run(it)) {
      modbus::put_be16(bytes + 2u * i, run_register(it, static_cast<uint16_t>(a - it.first)));
      continue;
    }
    uint32_t v = od_.get(it.row);
    if (w.bit_table) {
      modbus::BitSpan{bytes, count}.set(i, (v & 1u) != 0);
      continue;
    }
    if (it.bits < 32) v &= (static_cast<uint32_t>(1) << it.bits) - 1u;
    if (it.width == 2) v = a == it.first ? v >> 16 : v & 0xFFFFu;
    modbus::put_be16(bytes + 2u * i, static_cast<uint16_t>(v));
  }
  return Exception::kNone;
}

Exception OdRegisterBank::write_value(const Item& it, uint32_t value, bool apply) {
  // covers() checked the rights of the map as the request began; a map
  // written by this very request may name another entry since, or none.
  if (it.row == ObjectDictionary::kNoRow || !(od_.attr(it.row) & canopen::kAttrWrite)) {
    return Exception::kIllegalDataAddress;
  }
  const uint16_t size = od_.size_of(it.row);
  if (it.bits < 32 && (value >> it.bits) != 0) return Exception::kServerDeviceFailure;
  uint8_t bytes[4];
  canopen::put_le32(bytes, value);
  if (size < 4 && (value >> (8 * size)) != 0) return Exception::kServerDeviceFailure;
  return exception_of(od_.write_row(it.row, bytes, size, apply));
}

Exception OdRegisterBank::exception_of(canopen::SdoAbort r) {
  if (r == canopen::kSdoOk) return Exception::kNone;
  // Not in the present state (e.g. 1010h while a save runs): busy, try later.
  return r == canopen::kAbortDeviceState ? Exception::kServerDeviceBusy : Exception::kServerDeviceFailure;
}

bool OdRegisterBank::is_run(const Item& it) const {
  return it.row != ObjectDictionary::kNoRow && (it.width > 2 || (od_.attr(it.row) & canopen::kAttrString));
}

// A number's bytes big-endian over the item's registers (high word first,
// like a 32-bit entry's two); a string's in order, the first character in
// a register's high byte. Bytes past the value read 0.
uint16_t OdRegisterBank::run_register(const Item& it, uint16_t k) const {
  uint8_t value[kRunBytes];
  memset(value, 0, sizeof value);
  od_.copy_out(it.row, value, sizeof value);
  if (od_.attr(it.row) & canopen::kAttrString) {
    return static_cast<uint16_t>((value[2u * k] << 8) | value[2u * k + 1u]);
  }
  const uint16_t word = static_cast<uint16_t>(it.width - 1u - k);
  return static_cast<uint16_t>(value[2u * word] | (value[2u * word + 1u] << 8));
}

Exception OdRegisterBank::write_run(const Item& it, const uint8_t* registers, bool apply) {
  if (!(od_.attr(it.row) & canopen::kAttrWrite)) return Exception::kIllegalDataAddress;
  const bool text = (od_.attr(it.row) & canopen::kAttrString) != 0;
  const uint16_t capacity = od_.capacity_of(it.row);
  const uint16_t n = static_cast<uint16_t>(2u * it.width);
  uint8_t value[kRunBytes];
  uint16_t len = capacity;
  for (uint16_t j = 0; j < n; ++j) {
    const uint8_t b = text ? registers[j] : registers[n - 1u - j];
    // The padding past the value (a 40-bit value's top byte, an odd
    // string's last) must be 0, as it reads.
    if (j >= capacity && b != 0) return Exception::kServerDeviceFailure;
    if (j < capacity) value[j] = b;
    // A VISIBLE_STRING ends at its first NUL (OCTET_STRING: all bytes).
    if (text && b == 0 && j < len && od_.type_of(it.row) == canopen::kVisibleString) len = j;
  }
  return exception_of(od_.write_row(it.row, value, len, apply));
}

namespace {
// Old values of the entries a multi-item write changed, to undo them if a
// later item is refused: the request takes effect whole or not at all.
// Every byte of an entry's capacity (a string's too, whatever its length).
struct Undo {
  static const uint8_t kMax = 24;
  static const uint8_t kBytes = profile::kWideTypes ? OdRegisterBank::kRunBytes : 4;
  uint16_t rows[kMax];
  uint8_t old[kMax][kBytes];
  uint8_t n = 0;
  void save(ObjectDictionary& od, uint16_t row) {
    if (n == kMax) return;
    rows[n] = row;
    memcpy(old[n], od.ram_untracked(row), od.capacity_of(row));
    ++n;
  }
  // The bytes saved, put back: no revision change (ram_untracked).
  void rollback(ObjectDictionary& od) {
    while (n > 0) {
      --n;
      memcpy(od.ram_untracked(rows[n]), old[n], od.capacity_of(rows[n]));
    }
  }
};
}  // namespace

Exception OdRegisterBank::write_registers(uint16_t start, modbus::ConstRegisterSpan values) {
  return write_items(Table::kHoldingRegisters, start, values.count, values.bytes);
}

Exception OdRegisterBank::write_coils(uint16_t start, modbus::ConstBitSpan values) {
  return write_items(Table::kCoils, start, values.count, values.bytes);
}

// A request takes effect whole or not at all, and nothing of it is carried
// out before all of it is accepted: a check step decides every item (limits,
// hooks without side effects) on the values before it, stored and then put
// back; only then the apply step, whose hooks act (save, reset, the RUN
// latch). A refused request leaves every observable state as it was.
Exception OdRegisterBank::write_items(Table table, uint16_t start, uint16_t count, const uint8_t* bytes) {
  const Exception ex = write_step(table, start, count, bytes, false);
  return ex != Exception::kNone ? ex : write_step(table, start, count, bytes, true);
}

// Coils and holding registers share one loop: item by item, each value
// checked by the OD (limits, hooks), all undone when one is refused.
Exception OdRegisterBank::write_step(Table table, uint16_t start, uint16_t count, const uint8_t* bytes,
                                     bool apply) {
  Undo undo;
  Walk w;
  begin(table, &w);
  const Item& it = w.item;
  Exception ex = Exception::kNone;
  for (uint16_t i = 0; i < count;) {
    if (!reach(&w, static_cast<uint16_t>(start + i))) {
      ex = Exception::kIllegalDataAddress;
      break;
    }
    undo.save(od_, it.row);
    if (profile::kWideTypes && is_run(it)) {
      ex = write_run(it, bytes + 2u * i, apply);
      if (ex != Exception::kNone) break;
      i = static_cast<uint16_t>(i + it.width);
      continue;
    }
    uint32_t v;
    if (w.bit_table) {
      v = modbus::packed_bit(bytes, i) ? 1u : 0u;
    } else {
      v = modbus::get_be16(bytes + 2u * i);
      if (it.width == 2) v = (v << 16) | modbus::get_be16(bytes + 2u * i + 2u);
    }
    ex = write_value(it, v, apply);
    if (ex != Exception::kNone) break;
    i = static_cast<uint16_t>(i + it.width);  // always 1 for coils
    // The map itself changed under the walk: it starts over on the new map.
    if (moves_walk(w, it.row)) begin(table, &w);
  }
  // One exit: a refused item undoes the request, and so does the check step.
  if (ex != Exception::kNone || !apply) undo.rollback(od_);
  return ex;
}

canopen::HookResult GatewayHandlers::register_map(void* bank, uint16_t index, uint8_t sub,
                                                  const uint8_t* data, bool) {
  return static_cast<OdRegisterBank*>(bank)->check_map_write(index, sub, data);
}

canopen::SdoAbort OdRegisterBank::check_map_write(uint16_t index, uint8_t sub, const uint8_t* data) const {
  const ObjectDictionary& od = od_;
  // The map's table and its entries (the rows of its index after sub 0).
  const bool holding = index == 0x2400;
  const bool input = index == 0x2401;
  const bool coils = index == 0x2402;
  const Table table = holding ? Table::kHoldingRegisters
                      : input ? Table::kInputRegisters
                      : coils ? Table::kCoils
                              : Table::kDiscreteInputs;
  const uint8_t capacity = holding ? kHoldingMapSize
                           : input ? kInputMapSize
                           : coils ? kCoilMapSize
                                   : kDiscreteMapSize;
  if (sub == 0) {
    if (data[0] > capacity) return canopen::kAbortValueTooHigh;
    return canopen::kSdoOk;
  }
  const uint32_t entry = canopen::le32(data);
  if (entry == 0) return canopen::kSdoOk;
  const uint16_t row = od.find(canopen::map_index(entry), canopen::map_sub(entry));
  if (row == ObjectDictionary::kNoRow) {
    return od.has_index(canopen::map_index(entry)) ? canopen::kAbortNoSubindex : canopen::kAbortNoObject;
  }
  const uint8_t bits = canopen::map_bits(entry);
  const uint16_t size = od.capacity_of(row);
  if (od.attr(row) & canopen::kAttrString) {
    // A register run of the whole string: 16 bits per 2 characters (where
    // the profile has the wide types; the type is read only then).
    if (profile::kWideTypes && !is_bit_table(table) && size <= kRunBytes &&
        bits == 16u * ((size + 1u) / 2u)) {
      const uint8_t type = od.type_of(row);
      if (type == canopen::kVisibleString || type == canopen::kOctetString) return canopen::kSdoOk;
    }
    return canopen::kAbortInvalidValue;
  }
  if (is_bit_table(table)) {
    if (bits != 1 || size != 1) return canopen::kAbortInvalidValue;
  } else if (!((bits >= 1 && bits <= 16 && bits <= size * 8u) ||
               // 24 and 32 bits (2 registers); wider in host builds
               (bits > 16 && bits == size * 8u && (profile::kWideTypes || size <= 4)))) {
    return canopen::kAbortInvalidValue;
  }
  return canopen::kSdoOk;
}

uint8_t OdDeviceIdentity::copy_object(uint8_t id, uint8_t* out, uint8_t capacity) {
  if (id == kVendorName) {
    static const char kVendor[] MB2CO_FLASH = "mb2co";
    const uint8_t n = sizeof kVendor - 1;
    for (uint8_t i = 0; i < n && i < capacity; ++i) out[i] = flash_byte(kVendor + i);
    return n;
  }
  const uint16_t row = od_.find(id == kProductCode ? 0x1008 : 0x100A, 0);
  if (row == ObjectDictionary::kNoRow) return 0;
  od_.copy_out(row, out, capacity);  // the first `capacity` bytes
  return static_cast<uint8_t>(od_.size_of(row));
}

}  // namespace gateway
}  // namespace mb2co
