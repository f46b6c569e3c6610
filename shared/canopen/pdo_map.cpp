#include "canopen/pdo_map.h"

#include <string.h>

#include "canopen/od_comm.h"

namespace mb2co {
namespace canopen {

SdoAbort pdo_check_entry(const ObjectDictionary& od, uint32_t entry, bool receive) {
  const uint16_t index = map_index(entry);
  const uint8_t bits = map_bits(entry);
  const uint16_t row = od.find(index, map_sub(entry));
  if (row == ObjectDictionary::kNoRow) {
    return od.has_index(index) ? kAbortNoSubindex : kAbortNoObject;
  }
  const uint8_t attr = od.attr(row);
  if (!(attr & kAttrPdo)) return kAbortNotMappable;
  if (map_is_dummy(entry)) {
    if (bits != od.type_bits(static_cast<uint8_t>(index))) return kAbortNotMappable;
    return kSdoOk;
  }
  if (!(attr & (receive ? kAttrWrite : kAttrRead))) return kAbortNotMappable;
  if (bits == 0 || bits > od.size_of(row) * 8u) return kAbortNotMappable;
  return kSdoOk;
}

SdoAbort pdo_check_mapping(const ObjectDictionary& od, uint16_t row0, uint8_t count, uint8_t max_count,
                           bool receive, uint16_t* bits) {
  if (count > max_count || count > kPdoMaxMapped) return kAbortMapLength;
  uint16_t total = 0;
  for (uint8_t s = 1; s <= count; ++s) {
    const uint32_t entry = od.get(static_cast<uint16_t>(row0 + s));
    const SdoAbort abort = pdo_check_entry(od, entry, receive);
    if (abort != kSdoOk) return abort;
    total = static_cast<uint16_t>(total + map_bits(entry));
  }
  if (total > 64) return kAbortMapLength;
  *bits = total;
  return kSdoOk;
}

SdoAbort pdo_check_map_write(const ObjectDictionary& od, uint32_t cob, uint16_t row0, uint8_t stride,
                             uint8_t sub, const uint8_t* data, bool receive) {
  if (!(cob & 0x80000000u)) return kAbortUnsupported;  // CiA 301: disable the PDO first
  if (sub == 0) {
    uint16_t bits = 0;
    return pdo_check_mapping(od, row0, data[0], static_cast<uint8_t>(stride - 1), receive, &bits);
  }
  if (od.get(row0) != 0) return kAbortUnsupported;  // sub 0 must be 0 first
  const uint32_t entry = le32(data);
  return entry == 0 ? kSdoOk : pdo_check_entry(od, entry, receive);
}

uint8_t pdo_mapped_bytes(const ObjectDictionary& od, uint16_t row0) {
  const uint8_t count = static_cast<uint8_t>(od.get(row0));
  uint16_t total = 0;
  for (uint8_t s = 1; s <= count && s <= kPdoMaxMapped; ++s) {
    total = static_cast<uint16_t>(total + map_bits(od.get(static_cast<uint16_t>(row0 + s))));
  }
  return static_cast<uint8_t>((total + 7) / 8);
}

// Copies `bits` bits from src starting at bit `src_at` to dst starting at bit
// `dst_at`; dst's other bits are kept. One copy for transmit and receive
// (smaller on the Uno: docs/performance.md).
// Whole bytes at byte boundaries (every mapping but BOOLEANs and bit fields)
// are copied as bytes; otherwise bit by bit with running masks (an AVR shifts
// by a variable count one bit per cycle).
static void copy_bits(uint8_t* dst, uint16_t dst_at, const uint8_t* src, uint16_t src_at, uint8_t bits) {
  dst += dst_at / 8;
  src += src_at / 8;
  if ((dst_at % 8) == 0 && (src_at % 8) == 0 && (bits % 8) == 0) {
    memcpy(dst, src, bits / 8);
    return;
  }
  uint8_t in = static_cast<uint8_t>(1u << (src_at % 8));
  uint8_t out = static_cast<uint8_t>(1u << (dst_at % 8));
  for (uint8_t i = 0; i < bits; ++i) {
    if (*src & in) {
      *dst = static_cast<uint8_t>(*dst | out);
    } else {
      *dst = static_cast<uint8_t>(*dst & ~out);
    }
    in = static_cast<uint8_t>(in << 1);
    if (in == 0) {
      in = 1;
      ++src;
    }
    out = static_cast<uint8_t>(out << 1);
    if (out == 0) {
      out = 1;
      ++dst;
    }
  }
}

// One walk over the mapping at `row0` for both directions (one copy of the
// loop in the image): transmit (rx_od == nullptr) copies the mapped values
// into tx_data (zeroed by the caller); receive writes the values in rx_data
// to the mapped objects of *rx_od (the same OD as `od`). Dummy entries and
// objects that vanished are skipped. Returns the total mapped bits.
static uint16_t transfer(const ObjectDictionary& od, uint16_t row0, uint8_t* tx_data, ObjectDictionary* rx_od,
                         const uint8_t* rx_data) {
  const uint8_t count = static_cast<uint8_t>(od.get(row0));
  uint16_t at = 0;
  for (uint8_t s = 1; s <= count && s <= kPdoMaxMapped; ++s) {
    const uint32_t entry = od.get(static_cast<uint16_t>(row0 + s));
    const uint8_t bits = map_bits(entry);
    if (at + bits > 64) break;
    const uint16_t row =
        map_is_dummy(entry) ? ObjectDictionary::kNoRow : od.find(map_index(entry), map_sub(entry));
    if (row != ObjectDictionary::kNoRow) {
      // Up to 64 bits (the widest numeric types; a PDO holds 64 bits).
      uint8_t value[kOdMaxNumericBytes] = {0, 0, 0, 0, 0, 0, 0, 0};
      if (rx_od == nullptr) {
        od.copy_out(row, value, sizeof value);
        copy_bits(tx_data, at, value, 0, bits);
      } else {
        copy_bits(value, 0, rx_data, at, bits);
        // An entry with a write hook takes the network's path: limits and its
        // owner may refuse the value (an output under local control), which
        // is then dropped as an SDO write would be refused. PDOs have no answer.
        // So does one wider than set()'s 32 bits (its limits checked too).
        if (od.hook_of(row) != kHookNone || od.size_of(row) > 4) {
          rx_od->write_row(row, value, od.size_of(row));
        } else {
          rx_od->set(row, le32(value));
        }
      }
    }
    at = static_cast<uint16_t>(at + bits);
  }
  return at;
}

uint8_t pdo_build(const ObjectDictionary& od, uint16_t row0, uint8_t data[8]) {
  memset(data, 0, 8);
  return static_cast<uint8_t>((transfer(od, row0, data, nullptr, nullptr) + 7) / 8);
}

void pdo_apply(ObjectDictionary& od, uint16_t row0, const uint8_t* data) {
  transfer(od, row0, nullptr, &od, data);
}

// Records of one kind are consecutive rows, each beginning with its sub 0.
void pdo_find_records(const ObjectDictionary& od, uint16_t comm_index, PdoRecords* out) {
  const uint16_t map_index = static_cast<uint16_t>(comm_index + 0x200u);
  out->comm0 = od.find(comm_index, 0);
  out->map0 = od.find(map_index, 0);
  out->map_stride = static_cast<uint8_t>(od.find(static_cast<uint16_t>(map_index + 1), 0) - out->map0);
}

bool can_id_restricted(uint32_t can_id) {
  if (can_id > 0x7FFu) return false;
  // 16-bit compares (callers pass 11-bit ids).
  const uint16_t id = static_cast<uint16_t>(can_id);
  return id <= 0x07F || (id >= 0x101 && id <= 0x180) || (id >= 0x581 && id <= 0x5FF) ||
         (id >= 0x601 && id <= 0x67F) || (id >= 0x6E0 && id <= 0x6FF) || id >= 0x701;
}

SdoAbort pdo_check_cob_id(uint32_t cur, uint32_t v) {
  if (v & 0x20000000u) return kAbortInvalidValue;  // 29-bit ids not supported
  const bool cur_valid = !(cur & 0x80000000u);
  const bool new_valid = !(v & 0x80000000u);
  // CiA 301: the CAN-ID of a valid PDO changes only after it is disabled.
  if (cur_valid && new_valid && (v & 0x7FFu) != (cur & 0x7FFu)) return kAbortInvalidValue;
  if (new_valid && can_id_restricted(v & 0x7FFu)) return kAbortInvalidValue;
  return kSdoOk;
}

}  // namespace canopen
}  // namespace mb2co
