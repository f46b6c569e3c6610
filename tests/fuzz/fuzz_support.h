// What the libFuzzer targets of tests/fuzz share: an abort with a reason,
// the textbook CRC-16/MODBUS (independent of shared/crc/crc16), and a
// snapshot of an OD's const entries.
#pragma once
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vector>

#include "canopen/can_frame.h"
#include "canopen/od.h"

namespace mb2co {
namespace fuzz {

inline void require(bool ok, const char* what) {
  if (!ok) {
    fprintf(stderr, "invariant violated: %s\n", what);
    abort();
  }
}

/// CRC-16/MODBUS bit by bit; over an ADU with its CRC it is 0 when right.
inline uint16_t crc16_modbus(const uint8_t* p, size_t n) {
  uint16_t crc = 0xFFFF;
  for (size_t i = 0; i < n; ++i) {
    crc = static_cast<uint16_t>(crc ^ p[i]);
    for (int b = 0; b < 8; ++b)
      crc = (crc & 1u) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001u) : static_cast<uint16_t>(crc >> 1);
  }
  return crc;
}

/// Every const entry's value, in row order. A $NODEID-relative const (the
/// SDO server's COB-IDs 1200h) follows the active node id by design (CiA 306),
/// so it is recorded less the node id: what must never change is its base.
inline std::vector<uint8_t> const_values(const canopen::ObjectDictionary& od) {
  std::vector<uint8_t> out;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const uint8_t a = od.attr(r);
    if (!(a & canopen::kAttrConst)) continue;
    uint8_t buf[64];
    const uint16_t n = od.copy_out(r, buf, sizeof buf);
    if ((a & canopen::kAttrNodeId) && n == 4) {
      uint32_t v = 0;
      memcpy(&v, buf, 4);  // little-endian host, as the OD's value block
      v -= od.node_id();
      memcpy(buf, &v, 4);
    }
    out.insert(out.end(), buf, buf + n);
  }
  return out;
}

/// Sinks that take every frame and byte and keep nothing.
inline bool drop_frame(void*, const CanFrame&) {
  return true;
}
inline bool drop_bytes(void*, const uint8_t*, uint16_t) {
  return true;
}

/// Aborts unless every stored numeric value is one its entry's type and
/// limits allow.
inline void require_all_allowed(const canopen::ObjectDictionary& od, const char* what) {
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const uint8_t a = od.attr(r);
    if (!(a & canopen::kAttrRam) || (a & canopen::kAttrString)) continue;
    require(od.value_allowed(r, od.ram(r), od.size_of(r)), what);
  }
}

/// The RAM value block (everything the device stores) as one byte range:
/// from the first row's value to the end of the last, and where each numeric
/// entry lies in it. Found once per input, so that a snapshot before each
/// write is one copy and a limits check after it looks only at the entries
/// that changed (walking every row for both was most of an execution).
struct ValueRange {
  struct Numeric {
    uint16_t row;
    uint16_t at;        ///< offset of its value in the range
    uint16_t capacity;  ///< bytes
  };
  const uint8_t* begin = nullptr;
  size_t size = 0;
  std::vector<Numeric> numerics;  ///< RAM entries that are not byte strings

  std::vector<uint8_t> snapshot() const { return std::vector<uint8_t>(begin, begin + size); }
  bool unchanged_since(const std::vector<uint8_t>& before) const {
    return before.size() == size && (size == 0 || memcmp(before.data(), begin, size) == 0);
  }
};
inline ValueRange value_range(const canopen::ObjectDictionary& od) {
  ValueRange v;
  const uint8_t* end = nullptr;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const uint8_t* p = od.ram(r);
    if (p == nullptr) continue;
    if (v.begin == nullptr || p < v.begin) v.begin = p;
    if (end == nullptr || p + od.capacity_of(r) > end) end = p + od.capacity_of(r);
  }
  v.size = v.begin == nullptr ? 0u : static_cast<size_t>(end - v.begin);
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const uint8_t a = od.attr(r);
    if (!(a & canopen::kAttrRam) || (a & canopen::kAttrString)) continue;
    v.numerics.push_back(
        ValueRange::Numeric{r, static_cast<uint16_t>(od.ram(r) - v.begin), od.capacity_of(r)});
  }
  return v;
}

/// Aborts unless every stored numeric value is one its entry's type and
/// limits allow (require_all_allowed), given that all were when `at_check`
/// (a snapshot of `range`) was taken: only the entries whose bytes changed
/// since are checked again. Takes the new snapshot.
inline void require_changed_allowed(const canopen::ObjectDictionary& od, const ValueRange& range,
                                    std::vector<uint8_t>& at_check, const char* what) {
  for (const ValueRange::Numeric& n : range.numerics) {
    const uint8_t* p = range.begin + n.at;
    if (memcmp(p, at_check.data() + n.at, n.capacity) == 0) continue;
    require(od.value_allowed(n.row, p, od.size_of(n.row)), what);
  }
  at_check = range.snapshot();
}

}  // namespace fuzz
}  // namespace mb2co
