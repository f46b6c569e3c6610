// PDO mapping (CiA 301 §7.2.2.3): a record of up to kPdoMaxMapped 32-bit
// entries (index << 16 | sub << 8 | length in bits). Packing is bit-granular
// and little-endian: entry k starts where entry k-1 ended. Entries 0002h–0007h
// are dummies: zeros on transmit, skipped on receive.
#pragma once
#include <stdint.h>

#include "canopen/od.h"

namespace mb2co {
namespace canopen {

constexpr uint16_t map_index(uint32_t entry) {
  return static_cast<uint16_t>(entry >> 16);
}
constexpr uint8_t map_sub(uint32_t entry) {
  return static_cast<uint8_t>(entry >> 8);
}
constexpr uint8_t map_bits(uint32_t entry) {
  return static_cast<uint8_t>(entry);
}
inline bool map_is_dummy(uint32_t entry) {
  return map_index(entry) >= 0x0002 && map_index(entry) <= 0x0007;
}

/// Can `entry` be mapped (receive: written by an RPDO; else read by a TPDO)?
SdoAbort pdo_check_entry(const ObjectDictionary& od, uint32_t entry, bool receive);
/// Validates the first `count` entries of the mapping record whose sub 0 is at
/// `row0`; *bits = their total length. 0 or the abort code of the first fault.
SdoAbort pdo_check_mapping(const ObjectDictionary& od, uint16_t row0, uint8_t count, uint8_t max_count,
                           bool receive, uint16_t* bits);
/// Validates a write to sub `sub` of the mapping record whose sub 0 is at
/// `row0` (stride rows long) of a PDO whose COB-ID is `cob` (CiA 301
/// procedure: the PDO disabled, then sub 0 = 0, entries, sub 0 = count).
SdoAbort pdo_check_map_write(const ObjectDictionary& od, uint32_t cob, uint16_t row0, uint8_t stride,
                             uint8_t sub, const uint8_t* data, bool receive);
/// Where one kind of PDO lives in this OD: the rows of its first
/// communication record (`comm_index` sub 0) and first mapping record
/// (comm_index + 200h, sub 0), and the mapping records' stride. One copy for
/// the RPDOs and the TPDOs (the Uno's flash).
struct PdoRecords {
  uint16_t comm0;      ///< records are 5 (RPDO) or 6 (TPDO) rows apart
  uint16_t map0;       ///< records are map_stride rows apart
  uint8_t map_stride;  ///< 1 + mapping entries per record in this OD (pdo_find_records)
};
void pdo_find_records(const ObjectDictionary& od, uint16_t comm_index, PdoRecords* out);
/// Builds the payload of the mapping at `row0`; returns its length in bytes.
uint8_t pdo_build(const ObjectDictionary& od, uint16_t row0, uint8_t data[8]);
/// Writes a received payload into the mapped objects. Entries with a write
/// hook go through ObjectDictionary::write_row (limits, hook): one the hook
/// refuses keeps its value.
void pdo_apply(ObjectDictionary& od, uint16_t row0, const uint8_t* data);
/// Mapped length in bytes of the mapping at `row0`.
uint8_t pdo_mapped_bytes(const ObjectDictionary& od, uint16_t row0);
/// CiA 301 §7.3.5: CAN-IDs no PDO may use.
bool can_id_restricted(uint32_t can_id);
/// Shared validation of a PDO COB-ID write (sub 1), also of the EMCY COB-ID
/// 1014h (same rules): `cur` is the stored value.
SdoAbort pdo_check_cob_id(uint32_t cur, uint32_t v);

}  // namespace canopen
}  // namespace mb2co
