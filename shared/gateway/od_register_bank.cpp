#include "gateway/od_register_bank.h"

#include <string.h>

#include "canopen/pdo_map.h"

namespace mb2co {
namespace gateway {

using canopen::ObjectDictionary;
using canopen::OdEntry;
using modbus::Exception;
using modbus::Table;

namespace {
bool is_bit_table(Table t) { return t == Table::kCoils || t == Table::kDiscreteInputs; }
uint8_t width_of(Table t, uint8_t bits) { return (!is_bit_table(t) && bits == 32) ? 2 : 1; }
}  // namespace

bool OdRegisterBank::locate(Table table, uint16_t address, Item* item) const {
  const uint16_t row0 = od_.find(map_index(table), 0);
  const uint8_t count = static_cast<uint8_t>(od_.get(row0));
  uint16_t at = 0;
  for (uint8_t s = 1; s <= count; ++s) {
    const uint32_t entry = od_.get(static_cast<uint16_t>(row0 + s));
    const uint8_t bits = canopen::map_bits(entry);
    const uint8_t width = entry == 0 ? 1 : width_of(table, bits);
    if (address < at + width) {
      item->row = entry == 0 ? ObjectDictionary::kNoRow : od_.find(canopen::map_index(entry), canopen::map_sub(entry));
      item->bits = bits;
      item->width = width;
      item->first = at;
      return true;
    }
    at = static_cast<uint16_t>(at + width);
  }
  return false;
}

bool OdRegisterBank::covers(Table table, modbus::Access access, uint16_t start, uint16_t count) {
  const uint32_t end = static_cast<uint32_t>(start) + count;
  for (uint32_t a = start; a < end;) {
    Item it;
    if (!locate(table, static_cast<uint16_t>(a), &it) || it.row == ObjectDictionary::kNoRow) return false;
    const OdEntry e = od_.entry(it.row);
    if (access == modbus::Access::kWrite) {
      if (!(e.attr & canopen::kAttrWrite)) return false;
      // A 32-bit value is written whole or not at all.
      if (it.first < start || it.first + it.width > end) return false;
    } else if (!(e.attr & canopen::kAttrRead)) {
      return false;
    }
    a = it.first + it.width;
  }
  return true;
}

Exception OdRegisterBank::read_bits(Table table, uint16_t start, modbus::BitSpan out) {
  for (uint16_t i = 0; i < out.count; ++i) {
    Item it;
    if (!locate(table, static_cast<uint16_t>(start + i), &it)) return Exception::kIllegalDataAddress;
    out.set(i, (od_.get(it.row) & 1u) != 0);
  }
  return Exception::kNone;
}

Exception OdRegisterBank::read_registers(Table table, uint16_t start, modbus::RegisterSpan out) {
  for (uint16_t i = 0; i < out.count; ++i) {
    const uint16_t a = static_cast<uint16_t>(start + i);
    Item it;
    if (!locate(table, a, &it)) return Exception::kIllegalDataAddress;
    uint32_t v = od_.get(it.row);
    if (it.bits < 32) v &= (static_cast<uint32_t>(1) << it.bits) - 1u;
    if (it.width == 2) v = a == it.first ? v >> 16 : v & 0xFFFFu;
    out.set(i, static_cast<uint16_t>(v));
  }
  return Exception::kNone;
}

Exception OdRegisterBank::write_value(const Item& it, uint32_t value) {
  const OdEntry e = od_.entry(it.row);
  const uint16_t size = od_.size_of(it.row);
  if (it.bits < 32 && (value >> it.bits) != 0) return Exception::kServerDeviceFailure;
  uint8_t bytes[4];
  canopen::put_le32(bytes, value);
  if (size < 4 && (value >> (8 * size)) != 0) return Exception::kServerDeviceFailure;
  return od_.write(e.index, e.sub, bytes, size) == canopen::kSdoOk ? Exception::kNone
                                                                    : Exception::kServerDeviceFailure;
}

namespace {
// Old values of the entries a multi-item write changed, to undo them if a
// later item is refused: the request takes effect whole or not at all.
struct Undo {
  static const uint8_t kMax = 24;
  uint16_t rows[kMax];
  uint8_t old[kMax][4];
  uint8_t n = 0;
  void save(ObjectDictionary& od, uint16_t row) {
    if (n == kMax) return;
    rows[n] = row;
    memcpy(old[n], od.ram(row), od.size_of(row));
    ++n;
  }
  void rollback(ObjectDictionary& od) {
    while (n > 0) {
      --n;
      memcpy(od.ram(rows[n]), old[n], od.size_of(rows[n]));
    }
  }
};
}  // namespace

Exception OdRegisterBank::write_registers(uint16_t start, modbus::ConstRegisterSpan values) {
  Undo undo;
  for (uint16_t i = 0; i < values.count;) {
    Item it;
    if (!locate(Table::kHoldingRegisters, static_cast<uint16_t>(start + i), &it)) {
      undo.rollback(od_);
      return Exception::kIllegalDataAddress;
    }
    uint32_t v = values.get(i);
    if (it.width == 2) v = (v << 16) | values.get(static_cast<uint16_t>(i + 1));
    undo.save(od_, it.row);
    const Exception ex = write_value(it, v);
    if (ex != Exception::kNone) {
      undo.rollback(od_);
      return ex;
    }
    i = static_cast<uint16_t>(i + it.width);
  }
  return Exception::kNone;
}

Exception OdRegisterBank::write_coils(uint16_t start, modbus::ConstBitSpan values) {
  Undo undo;
  for (uint16_t i = 0; i < values.count; ++i) {
    Item it;
    if (!locate(Table::kCoils, static_cast<uint16_t>(start + i), &it)) {
      undo.rollback(od_);
      return Exception::kIllegalDataAddress;
    }
    undo.save(od_, it.row);
    const Exception ex = write_value(it, values.get(i) ? 1u : 0u);
    if (ex != Exception::kNone) {
      undo.rollback(od_);
      return ex;
    }
  }
  return Exception::kNone;
}

uint32_t OdRegisterBank::check_map_write(const ObjectDictionary& od, uint16_t index, uint8_t sub,
                                         const uint8_t* data) {
  const Table table = index == 0x2400 ? Table::kHoldingRegisters
                      : index == 0x2401 ? Table::kInputRegisters
                      : index == 0x2402 ? Table::kCoils
                                        : Table::kDiscreteInputs;
  const uint16_t row0 = od.find(index, 0);
  const uint16_t capacity = static_cast<uint16_t>(od.first_row(static_cast<uint16_t>(index + 1)) - row0 - 1);
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
  const OdEntry e = od.entry(row);
  const uint8_t bits = canopen::map_bits(entry);
  const uint16_t size = od.size_of(row);
  if (e.attr & canopen::kAttrString) return canopen::kAbortInvalidValue;
  if (is_bit_table(table)) {
    if (bits != 1 || size != 1) return canopen::kAbortInvalidValue;
  } else if (!((bits >= 1 && bits <= 16 && bits <= size * 8u) || (bits == 32 && size == 4))) {
    return canopen::kAbortInvalidValue;
  }
  return canopen::kSdoOk;
}

uint8_t OdDeviceIdentity::copy_object(uint8_t id, uint8_t* out, uint8_t capacity) {
  if (id == kVendorName) {
    static const char kVendor[] = "mb2co";
    const uint8_t n = sizeof kVendor - 1;
    memcpy(out, kVendor, n < capacity ? n : capacity);
    return n;
  }
  const uint16_t row = od_.find(id == kProductCode ? 0x1008 : 0x100A, 0);
  if (row == ObjectDictionary::kNoRow) return 0;
  const uint16_t n = od_.size_of(row);
  uint8_t buf[32];
  od_.copy_out(row, buf, sizeof buf);
  memcpy(out, buf, n < capacity ? n : capacity);
  return static_cast<uint8_t>(n);
}

}  // namespace gateway
}  // namespace mb2co
