#include "canopen/param_storage.h"

#include "modbus/crc16.h"

namespace mb2co {
namespace canopen {

// Two slots of kSlotBytes, slot k at k * kSlotBytes, each:
//   magic (2) | sequence number (2) | payload length (2) | payload | CRC-16 (2)
// The CRC (CRC-16/MODBUS, the routine the gateway has anyway) covers the
// payload, then the header; unlike a sum modulo 255 it tells 00h from FFh, so
// an erased byte (EEPROM FFh) never passes. A save writes the slot that does
// not hold the newest set: its magic made invalid first, the header last.
// Whenever power fails, the other slot still holds the old set, and a boot
// finds the old or the new one. (A slot damaged otherwise, e.g. a worn EEPROM
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

const uint16_t kFailed = 0xFFFF;

/// The one walk over a slot's payload, row by row: `save` writes every row
/// (and goes on with *crc), else the rows with from <= index <= to are read
/// into the OD and each checked against its entry's limits (loading bypasses
/// the write path; a CRC cannot tell a value that was never allowed).
/// Returns the payload length, kFailed when the storage fails, a loaded
/// value is not allowed, or the payload would not fit the slot.
uint16_t walk(ObjectDictionary& od, const ParamStorage& st, uint16_t at, bool save, uint16_t from,
              uint16_t to, uint16_t* crc) {
  uint16_t len = 0;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    if (!param_is_saved(od, r)) continue;
    const uint16_t n = od.capacity_of(r);
    const uint16_t where = static_cast<uint16_t>(at + kHeader + len);
    len = static_cast<uint16_t>(len + n);
    if (len > kMaxPayload) return kFailed;
    const uint16_t index = od.index_of(r);
    uint8_t* p = od.ram_untracked(r);
    if (save) {
      if (!st.write(st.ctx, where, p, n)) return kFailed;
      *crc = modbus::crc16(p, n, *crc);
    } else if (index >= from && index <= to &&
               (!st.read(st.ctx, where, p, n) || (n <= 4 && !od.value_allowed(r, p, n)))) {
      return kFailed;
    }
  }
  return len;
}

/// True when the slot at `at` with `header` carries a right CRC over the
/// payload length this OD saves (read byte by byte: no buffer).
bool crc_right(const ObjectDictionary& od, const ParamStorage& st, uint16_t at, const uint8_t* header) {
  uint16_t len = 0;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    if (param_is_saved(od, r)) len = static_cast<uint16_t>(len + od.capacity_of(r));
  }
  if (le16(header) != kMagic || le16(header + 4) != len || len > kMaxPayload) return false;
  uint16_t crc = modbus::kCrcInit;
  for (uint16_t i = 0; i < len + kCrcBytes; ++i) {
    if (i == len) crc = modbus::crc16(header, kHeader, crc);  // payload, header, then the CRC bytes
    uint8_t b;
    if (!st.read(st.ctx, static_cast<uint16_t>(at + kHeader + i), &b, 1)) return false;
    crc = modbus::crc16(&b, 1, crc);
  }
  return crc == 0;  // residue 0: the CRC matches
}

/// Both headers (erased, invalidated or unreadable: magic 0); returns the
/// slot whose header claims the newer set first (0 or 1). Sequence numbers
/// compare wrap-safe: they only ever count up by one.
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

bool params_save(ObjectDictionary& od, const ParamStorage& st) {
  uint8_t headers[2][kHeader];
  const uint8_t newest = read_headers(st, headers);
  const bool had_set = le16(headers[newest]) == kMagic;
  const uint16_t sequence = had_set ? static_cast<uint16_t>(le16(headers[newest] + 2) + 1u) : 1u;
  // The target is the other slot, unless the newest header's set fails its
  // CRC (damaged, or the remains of a cut save): then that slot, as the other
  // may hold the only loadable set. With no set at all, slot 0.
  uint8_t target = newest;
  if (had_set && crc_right(od, st, newest ? kSlotBytes : 0, headers[newest])) target ^= 1u;
  const uint16_t at = target ? kSlotBytes : 0;
  uint8_t* header = headers[0];
  header[0] = header[1] = 0;  // magic 0: not valid while the payload changes
  if (!st.write(st.ctx, at, header, 2) || !barrier(st)) return false;
  uint16_t crc = modbus::kCrcInit;
  const uint16_t len = walk(od, st, at, true, 0, 0, &crc);
  if (len == kFailed) return false;
  put_le16(header, kMagic);
  put_le16(header + 2, sequence);
  put_le16(header + 4, len);
  uint8_t check[kCrcBytes];
  put_le16(check, modbus::crc16(header, kHeader, crc));  // low byte first, as on a Modbus line
  if (!st.write(st.ctx, static_cast<uint16_t>(at + kHeader + len), check, kCrcBytes) || !barrier(st))
    return false;
  return st.write(st.ctx, at, header, kHeader) && barrier(st);
}

ParamLoad params_load(ObjectDictionary& od, const ParamStorage& st, uint16_t from_index, uint16_t to_index) {
  uint8_t headers[2][kHeader];
  const uint8_t newest = read_headers(st, headers);
  bool damaged = false;
  for (uint8_t k = 0; k < 2; ++k) {
    const uint8_t slot = k == 0 ? newest : static_cast<uint8_t>(1u - newest);
    const uint16_t magic = le16(headers[slot]);
    if (magic == 0x0000 || magic == 0xFFFF) continue;  // erased or invalidated: no set, no damage
    const uint16_t at = static_cast<uint16_t>(slot * kSlotBytes);
    uint16_t unused = 0;
    if (crc_right(od, st, at, headers[slot]) &&
        walk(od, st, at, false, from_index, to_index, &unused) != kFailed) {
      return damaged ? ParamLoad::kLoadedOneDamaged : ParamLoad::kLoaded;
    }
    damaged = true;
    od.restore_defaults(from_index, to_index);  // nothing of a refused set stays
  }
  return damaged ? ParamLoad::kDamaged : ParamLoad::kNone;
}

}  // namespace canopen
}  // namespace mb2co
