#include "canopen/param_storage.h"

#include "crc/crc16.h"

namespace mb2co {
namespace canopen {

// Two slots of kSlotBytes, slot k at k * kSlotBytes, each:
//   magic (2) | sequence number (2) | payload length (2) | payload | CRC-16 (2)
// The CRC (CRC-16/MODBUS, the routine the gateway has anyway) covers the
// payload, then the header; unlike a sum modulo 255 it tells 00h from FFh, so
// an erased byte (EEPROM FFh) never passes. A save (ParamSave) writes the
// slot that does not hold the newest set: its magic made invalid first, the
// magic last. Whenever power fails, the other slot still holds the old set,
// and a boot finds the old or the new one. (A slot damaged otherwise, e.g. a worn EEPROM
// cell, is caught by its CRC at the next boot: the other slot then applies.)
static const uint16_t kMagic = 0x3243;  // "C2": the two-slot layout
static const uint16_t kHeader = 6;
static const uint16_t kCrcBytes = 2;
/// Half of the Uno's 1 KiB EEPROM (the storages of mb2co-node and the
/// simulator are as large). A payload that does not fit is not saved.
static const uint16_t kSlotBytes = 512;
static const uint16_t kMaxPayload = kSlotBytes - kHeader - kCrcBytes;

bool param_is_saved(const ObjectDictionary& od, uint16_t row) {
  if ((od.attr(row) & (kAttrRam | kAttrWrite | kAttrCommand)) != (kAttrRam | kAttrWrite)) return false;
  return od.hook_of(row) != kHookStore && od.index_of(row) != 0x1003;
}

namespace {

// Node-id-relative COB-IDs (kAttrNodeId rows: 1014h, the PDO COB-IDs), as
// CANopenNode stores them: a COB-ID that is its default's, base + the node
// id in force, is saved as "base + the node id", and loaded as base + the
// node id in force then, so it follows every change of the id (a station
// given its id over Modbus and saved sends its TPDOs and EMCY on its own
// id after the power cycle). A COB-ID set to anything else is kept as set.
// The mark is bit 11 of an 11-bit COB-ID, where CiA 301 has 0 (bits 11-28
// of a COB-ID with bit 29 clear), so no value a master can set carries it;
// unlike CANopenNode's "the base alone" the mark keeps a COB-ID set to the
// base itself as set.
// Worked on the little-endian bytes with 16-bit arithmetic, in one function
// for both ways (the Uno's flash): the CAN id is byte 0 and bits 0-2 of
// byte 1, the mark bit 3 of byte 1, bit 29 (a 29-bit id) bit 5 of byte 3.
const uint8_t kMarkBit = 0x08;      // bit 11 in byte 1
const uint8_t kExtendedBit = 0x20;  // bit 29 in byte 3: a 29-bit CAN id, never relative

/// In place, the 4 value bytes of `row` on their way into a slot
/// (`to_saved`) or out of one, for the node id in force now.
__attribute__((noinline)) void convert_cob_id(const ObjectDictionary& od, uint16_t row, uint8_t* bytes,
                                              bool to_saved) {
  if (!(od.attr(row) & kAttrNodeId) || (bytes[3] & kExtendedBit)) return;
  uint16_t id = static_cast<uint16_t>(bytes[0] | ((bytes[1] & 0x07) << 8));
  uint8_t mark = 0;
  if (to_saved) {
    // (the low 16 bits only: no 32-bit compare on the AVR)
    if (id != (static_cast<uint16_t>(od.default_value(row)) & 0x7FFu)) return;  // not base + the id in force
    id = static_cast<uint16_t>(id - od.node_id());
    mark = kMarkBit;
  } else {
    if (!(bytes[1] & kMarkBit)) return;
    id = static_cast<uint16_t>(id + od.node_id());
  }
  bytes[0] = static_cast<uint8_t>(id);
  bytes[1] = static_cast<uint8_t>((bytes[1] & 0xF0) | mark | ((id >> 8) & 0x07));
}

/// Bytes of the payload: every saved row at its capacity, in row order.
uint16_t payload_length(const ObjectDictionary& od) {
  uint16_t len = 0;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    if (param_is_saved(od, r)) len = static_cast<uint16_t>(len + od.capacity_of(r));
  }
  return len;
}

/// Reads the payload of the slot at `at` row by row: the rows with from <=
/// index <= to into the OD, and every numeric row checked against its
/// entry's limits, in the range or not (loading bypasses the write path; a
/// CRC cannot tell a value that was never allowed). A set is valid or not
/// whole, whatever area a reset loads: a reset communication never takes the
/// communication area of a set a reset node refused. False when the storage
/// fails or a saved value is not allowed.
bool load_rows(ObjectDictionary& od, const ParamStorage& st, uint16_t at, uint16_t from, uint16_t to) {
  uint16_t where = static_cast<uint16_t>(at + kHeader);
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    if (!param_is_saved(od, r)) continue;
    const uint16_t n = od.capacity_of(r);
    const uint16_t index = od.index_of(r);
    uint8_t outside[4];  // a value of a row outside the range, read to be checked only
    const bool inside = index >= from && index <= to;
    uint8_t* p = inside ? od.ram_untracked(r) : outside;
    if (inside || n <= 4) {
      if (!st.read(st.ctx, where, p, n)) return false;
      convert_cob_id(od, r, p, false);
      if (n <= 4 && !od.value_allowed(r, p, n)) return false;
    }
    where = static_cast<uint16_t>(where + n);
  }
  return true;
}

/// True when the slot at `at` with `header` carries a right CRC over the
/// payload length this OD saves (read byte by byte: no buffer).
bool crc_right(const ObjectDictionary& od, const ParamStorage& st, uint16_t at, const uint8_t* header) {
  const uint16_t len = payload_length(od);
  if (le16(header) != kMagic || le16(header + 4) != len || len > kMaxPayload) return false;
  uint16_t crc = kCrcInit;
  for (uint16_t i = 0; i < len + kCrcBytes; ++i) {
    if (i == len) crc = crc16(header, kHeader, crc);  // payload, header, then the CRC bytes
    uint8_t b;
    if (!st.read(st.ctx, static_cast<uint16_t>(at + kHeader + i), &b, 1)) return false;
    crc = crc16(&b, 1, crc);
  }
  return crc == 0;  // residue 0: the CRC matches
}

/// Both headers (erased, invalidated or unreadable: magic 0); returns the
/// slot whose header claims the newer set first (0 or 1). Sequence numbers
/// count up by one per save, modulo 2^16 (0000h follows FFFFh): of two, the
/// newer is the one 1..32767 ahead (their difference as int16). A header's
/// claim is only a claim: its CRC says whether the set is there.
uint8_t read_headers(const ParamStorage& st, uint8_t (*headers)[kHeader]) {
  for (uint8_t k = 0; k < 2; ++k) {
    if (!st.read(st.ctx, static_cast<uint16_t>(k * kSlotBytes), headers[k], kHeader))
      headers[k][0] = headers[k][1] = 0;
  }
  const bool set0 = le16(headers[0]) == kMagic;
  const bool set1 = le16(headers[1]) == kMagic;
  if (set0 && set1) return static_cast<int16_t>(le16(headers[1] + 2) - le16(headers[0] + 2)) > 0 ? 1 : 0;
  return set1 ? 1 : 0;
}

bool barrier(const ParamStorage& st) {
  return st.barrier == nullptr || st.barrier(st.ctx);
}

}  // namespace

bool params_erase(const ParamStorage& st) {
  const uint8_t zero[2] = {0, 0};
  return st.write(st.ctx, 0, zero, 2) && st.write(st.ctx, kSlotBytes, zero, 2);
}

ParamLoad params_load(ObjectDictionary& od, const ParamStorage& st, uint16_t from_index, uint16_t to_index) {
  uint8_t headers[2][kHeader];
  const uint8_t newest = read_headers(st, headers);
  // Both slots' CRCs are checked, whichever loads: a bit flipped in the
  // newest slot's sequence number makes it claim to be the older one, and
  // only its CRC tells (loading the older set then is a rollback the
  // operator must hear of). A slot without a magic (erased, or invalidated
  // by a save that began there) holds no set; any other slot whose CRC
  // fails is damage, reported whichever set loads.
  bool loaded = false;
  bool damaged = false;
  for (uint8_t k = 0; k < 2; ++k) {
    const uint8_t slot = static_cast<uint8_t>(newest ^ k);
    const uint16_t magic = le16(headers[slot]);
    if (magic == 0x0000 || magic == 0xFFFF) continue;  // erased or invalidated: no set, no damage
    const uint16_t at = static_cast<uint16_t>(slot * kSlotBytes);
    if (!crc_right(od, st, at, headers[slot])) {
      damaged = true;
    } else if (!loaded) {
      loaded = load_rows(od, st, at, from_index, to_index);
      if (!loaded) {
        damaged = true;
        od.restore_defaults(from_index, to_index);  // nothing of a refused set stays
      }
    }
  }
  if (loaded) return damaged ? ParamLoad::kLoadedOneDamaged : ParamLoad::kLoaded;
  return damaged ? ParamLoad::kDamaged : ParamLoad::kNone;
}

// ---- ParamSave ----------------------------------------------------------------
// The bytes of a save as one sequence, k = next_ - 1, with end = the slot's
// used length (header, payload, CRC):
//   k in [0, 2)       slot offset k: 0, the magic made invalid    barrier after
//   k in [2, end)     slot offset k: sequence number and length, the payload,
//                     the CRC                                      barrier after
//   k in [end, end+2) slot offset k - end: the magic; the set counts from
//                     its last byte on                             barrier after

void ParamSave::start(const ObjectDictionary& od, const ParamStorage& st) {
  uint8_t headers[2][kHeader];
  const uint8_t newest = read_headers(st, headers);
  const bool had_set = le16(headers[newest]) == kMagic;
  sequence_ = had_set ? static_cast<uint16_t>(le16(headers[newest] + 2) + 1u) : 1u;
  // The target is the other slot, unless the newest header's set fails its
  // CRC (damaged, or the remains of a cut save): then that slot, as the other
  // may hold the only loadable set. With no set at all, slot 0.
  slot_ = newest;
  if (had_set && crc_right(od, st, newest ? kSlotBytes : 0, headers[newest]))
    slot_ = static_cast<uint8_t>(slot_ ^ 1u);
  length_ = payload_length(od);
  crc_ = kCrcInit;
  next_ = 1;
  next_row(od, 0);
}

void ParamSave::next_row(const ObjectDictionary& od, uint16_t from) {
  in_row_ = 0;
  for (row_ = from; row_ < od.row_count(); ++row_) {
    const uint16_t n = od.capacity_of(row_);
    if (!param_is_saved(od, row_) || n == 0) continue;
    // Copied now: a network write during the save cannot tear the entry.
    const uint8_t* p = od.ram(row_);
    for (uint8_t i = 0; i < sizeof entry_ && i < n; ++i) entry_[i] = p[i];
    convert_cob_id(od, row_, entry_, true);
    return;
  }
}

ParamSave::Result ParamSave::step(const ObjectDictionary& od, const ParamStorage& st) {
  const uint16_t end = static_cast<uint16_t>(length_ + kHeader + kCrcBytes);
  bool ok = length_ <= kMaxPayload;
  for (uint8_t n = kBytesPerPass; ok && n != 0; --n) {
    if (st.ready != nullptr && !st.ready(st.ctx)) return kRunning;
    const uint16_t k = static_cast<uint16_t>(next_ - 1);
    const uint16_t offset = k < end ? k : static_cast<uint16_t>(k - end);
    uint8_t h[kHeader];
    put_le16(h, kMagic);
    put_le16(h + 2, sequence_);
    put_le16(h + 4, length_);
    uint8_t b;
    if (offset < kHeader) {
      b = k < 2 ? 0 : h[offset];
    } else if (offset < end - kCrcBytes) {
      b = in_row_ < sizeof entry_ ? entry_[in_row_] : od.ram(row_)[in_row_];
    } else {
      if (offset == end - kCrcBytes) crc_ = crc16(h, kHeader, crc_);           // payload, then header
      b = static_cast<uint8_t>(offset == end - kCrcBytes ? crc_ : crc_ >> 8);  // low byte first
    }
    ok = st.write(st.ctx, static_cast<uint16_t>((slot_ ? kSlotBytes : 0) + offset), &b, 1);
    const uint16_t done = next_++;
    if (offset >= kHeader && offset < end - kCrcBytes) {
      crc_ = crc16(&b, 1, crc_);
      if (++in_row_ == od.capacity_of(row_)) next_row(od, static_cast<uint16_t>(row_ + 1));
    }
    if (ok && (done == 2 || done == end || done == end + 2u)) ok = barrier(st);
    if (ok && done == end + 2u) {
      next_ = 0;
      return kDone;
    }
  }
  if (ok) return kRunning;
  next_ = 0;
  return kFailed;
}

}  // namespace canopen
}  // namespace mb2co
