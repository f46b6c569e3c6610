#include "canopen/pdo_map.h"

#include <string.h>

#include "canopen/od_comm.h"

namespace mb2co {
namespace canopen {

uint32_t pdo_check_entry(const ObjectDictionary& od, uint32_t entry, bool receive) {
  const uint16_t index = map_index(entry);
  const uint8_t bits = map_bits(entry);
  const uint16_t row = od.find(index, map_sub(entry));
  if (row == ObjectDictionary::kNoRow) {
    return od.has_index(index) ? kAbortNoSubindex : kAbortNoObject;
  }
  const OdEntry e = od.entry(row);
  if (!(e.attr & kAttrPdo)) return kAbortNotMappable;
  if (map_is_dummy(entry)) {
    if (bits != od.type_bits(static_cast<uint8_t>(index))) return kAbortNotMappable;
    return kSdoOk;
  }
  if (!(e.attr & (receive ? kAttrWrite : kAttrRead))) return kAbortNotMappable;
  if (bits == 0 || bits > od.size_of(row) * 8u) return kAbortNotMappable;
  return kSdoOk;
}

uint32_t pdo_check_mapping(const ObjectDictionary& od, uint16_t row0, uint8_t count,
                           uint8_t max_count, bool receive, uint16_t* bits) {
  if (count > max_count || count > kPdoMaxMapped) return kAbortMapLength;
  uint16_t total = 0;
  for (uint8_t s = 1; s <= count; ++s) {
    const uint32_t entry = od.get(static_cast<uint16_t>(row0 + s));
    const uint32_t abort = pdo_check_entry(od, entry, receive);
    if (abort != kSdoOk) return abort;
    total = static_cast<uint16_t>(total + map_bits(entry));
  }
  if (total > 64) return kAbortMapLength;
  *bits = total;
  return kSdoOk;
}

uint32_t pdo_check_map_write(const ObjectDictionary& od, uint32_t cob, uint16_t row0,
                             uint8_t stride, uint8_t sub, const uint8_t* data, bool receive) {
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

// Copies `bits` bits from src (starting at bit 0) to dst starting at bit `at`.
// Whole bytes at a byte boundary (every mapping but BOOLEANs and bit fields)
// are copied as bytes; otherwise bit by bit with running masks (an AVR shifts
// by a variable count one bit per cycle).
static void put_bits(uint8_t* dst, uint16_t at, const uint8_t* src, uint8_t bits) {
  dst += at / 8;
  if ((at % 8) == 0 && (bits % 8) == 0) {
    memcpy(dst, src, bits / 8);
    return;
  }
  uint8_t in = 1;
  uint8_t out = static_cast<uint8_t>(1u << (at % 8));
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

// Copies `bits` bits from src starting at bit `at` to dst (zeroed) from bit 0.
static void get_bits(uint8_t* dst, const uint8_t* src, uint16_t at, uint8_t bits) {
  src += at / 8;
  if ((at % 8) == 0 && (bits % 8) == 0) {
    memcpy(dst, src, bits / 8);
    return;
  }
  uint8_t in = static_cast<uint8_t>(1u << (at % 8));
  uint8_t out = 1;
  for (uint8_t i = 0; i < bits; ++i) {
    if (*src & in) *dst = static_cast<uint8_t>(*dst | out);
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

// Calls fn(row, bit_offset, bits) for every mapped entry that is not a dummy
// (row kNoRow if the object vanished) and returns the total mapped bits.
template <class Fn>
static uint16_t for_each_mapped(const ObjectDictionary& od, uint16_t row0, Fn fn) {
  const uint8_t count = static_cast<uint8_t>(od.get(row0));
  uint16_t at = 0;
  for (uint8_t s = 1; s <= count && s <= kPdoMaxMapped; ++s) {
    const uint32_t entry = od.get(static_cast<uint16_t>(row0 + s));
    const uint8_t bits = map_bits(entry);
    if (at + bits > 64) break;
    if (!map_is_dummy(entry)) fn(od.find(map_index(entry), map_sub(entry)), at, bits);
    at = static_cast<uint16_t>(at + bits);
  }
  return at;
}

uint8_t pdo_build(const ObjectDictionary& od, uint16_t row0, uint8_t data[8]) {
  memset(data, 0, 8);
  const uint16_t bits = for_each_mapped(od, row0, [&](uint16_t row, uint16_t at, uint8_t n) {
    if (row == ObjectDictionary::kNoRow) return;
    uint8_t value[4] = {0, 0, 0, 0};
    od.copy_out(row, value, sizeof value);
    put_bits(data, at, value, n);
  });
  return static_cast<uint8_t>((bits + 7) / 8);
}

void pdo_apply(ObjectDictionary& od, uint16_t row0, const uint8_t* data) {
  for_each_mapped(od, row0, [&](uint16_t row, uint16_t at, uint8_t n) {
    if (row == ObjectDictionary::kNoRow) return;
    uint8_t value[4] = {0, 0, 0, 0};
    get_bits(value, data, at, n);
    // An entry with a write hook takes the network's path: limits and its
    // owner may refuse the value (an output under local control), which is
    // then dropped as an SDO write would be refused. PDOs have no answer.
    if (od.hook_of(row) != kHookNone) {
      od.write_row(row, value, od.size_of(row));
    } else {
      od.set(row, le32(value));
    }
  });
}

uint8_t pdo_map_stride(const ObjectDictionary& od, uint16_t first_index) {
  return static_cast<uint8_t>(od.first_row(static_cast<uint16_t>(first_index + 1)) -
                              od.first_row(first_index));
}

bool can_id_restricted(uint32_t id) {
  return id == 0x000 || (id >= 0x001 && id <= 0x07F) || (id >= 0x101 && id <= 0x180) ||
         (id >= 0x581 && id <= 0x5FF) || (id >= 0x601 && id <= 0x67F) ||
         (id >= 0x6E0 && id <= 0x6FF) || (id >= 0x701 && id <= 0x7FF);
}

uint32_t pdo_check_cob_id(uint32_t cur, uint32_t v) {
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
