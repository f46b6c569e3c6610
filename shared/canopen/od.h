// The Object Dictionary: constant rows (flash on AVR) + a caller-owned RAM
// value block. Lookup is a binary search over the sorted rows: O(log n).
// Every access from the network goes through read()/write(), which apply
// access rights, sizes, limits and the owning service's write hook, and
// answer with a CiA 301 SDO abort code (0 = done).
#pragma once
#include <stdint.h>

#include "canopen/od_define.h"
#include "canopen/od_types.h"
#include "canopen/sdo_abort.h"

namespace mb2co {
namespace canopen {

/// Validates (and lets the owning service take note of) a write before it is
/// stored. `data`/`len` are the new value, little-endian as on the bus.
/// Returns 0 to accept, kHookHandled when the hook has done all there is to do
/// (the written value is not stored, e.g. the "save" signature of 1010h), or an
/// SDO abort code to refuse (nothing is stored).
typedef uint32_t (*OdWriteHook)(void* ctx, uint8_t hook, uint16_t index, uint8_t sub,
                                const uint8_t* data, uint16_t len);

const uint32_t kHookHandled = 0xFFFFFFFFu;

class ObjectDictionary {
 public:
  static const uint16_t kNoRow = 0xFFFF;

  /// `values` must hold def.values_size bytes and outlive the OD (caller-owned).
  ObjectDictionary(const OdDefinition& def, uint8_t* values);

  void set_node_id(uint8_t node_id) {
    node_id_ = node_id;  // node-id-relative constants read differently now
    touch();
  }
  uint8_t node_id() const { return node_id_; }
  void set_write_hook(OdWriteHook hook, void* ctx) {
    hook_ = hook;
    hook_ctx_ = ctx;
  }
  const OdDefinition& definition() const { return def_; }

  // ---- lookup ---------------------------------------------------------------
  /// Row number of (index, sub), or kNoRow.
  uint16_t find(uint16_t index, uint8_t sub) const;
  /// True when some sub-entry of `index` exists.
  bool has_index(uint16_t index) const;
  /// rows[i] = find(indices[i], 0) for `count` indices from a MB2CO_FLASH
  /// table: the services' start-up lookups as one loop (-92 B on the Uno).
  void find_rows(const uint16_t* indices, uint8_t count, uint16_t* rows) const;
  /// First row of `index` (kNoRow if absent); rows of one index are contiguous.
  uint16_t first_row(uint16_t index) const;
  uint16_t row_count() const { return def_.row_count; }
  /// Copy of a row's metadata (from flash on AVR). Hot paths read single
  /// fields instead (attr(), index_of(), ...): one row is 12 bytes of flash.
  OdEntry entry(uint16_t row) const { return flash_read(&def_.rows[row]); }
  /// Single fields of a row (OdAttr bits, index, sub-index).
  MB2CO_INLINE uint8_t attr(uint16_t row) const { return flash_read(&def_.rows[row].attr); }
  MB2CO_INLINE uint16_t index_of(uint16_t row) const { return flash_read(&def_.rows[row].index); }
  MB2CO_INLINE uint8_t sub_of(uint16_t row) const { return flash_read(&def_.rows[row].sub); }
  /// OdHook of a row (kHookNone: no service validates writes to it).
  MB2CO_INLINE uint8_t hook_of(uint16_t row) const {
    return static_cast<uint8_t>(
        flash_read(reinterpret_cast<const uint8_t*>(&def_.rows[row]) + kOdEntryTypeHookOffset) >> 4);
  }
  /// Bit length of a numeric data type, read from data-type entries
  /// 0001h–0007h of this very OD (0 when the type has no such entry).
  uint8_t type_bits(uint8_t type) const;
  /// Current size in bytes: numeric types from their data-type entry, strings
  /// their current text length.
  uint16_t size_of(uint16_t row) const;
  /// Bytes a write may carry at most (strings: capacity).
  uint16_t capacity_of(uint16_t row) const;

  // ---- network access (rights, sizes, limits, hooks) ------------------------
  /// Reads (index, sub) into buf (cap bytes); *len = bytes. 0 or abort code.
  uint32_t read(uint16_t index, uint8_t sub, uint8_t* buf, uint16_t cap, uint16_t* len) const;
  /// Checks what a read would answer without copying; *row = the row.
  uint32_t check_read(uint16_t index, uint8_t sub, uint16_t* row) const;
  /// Checks rights of a write before data arrives (segmented download).
  uint32_t check_write(uint16_t index, uint8_t sub, uint16_t* row) const;
  /// Writes (index, sub) from data/len: rights, size, limits, hook, then store.
  uint32_t write(uint16_t index, uint8_t sub, const uint8_t* data, uint16_t len);
  /// write() of a row whose access rights the caller has checked (a mapped
  /// RPDO entry): size, limits, hook, then store.
  uint32_t write_row(uint16_t row, const uint8_t* data, uint16_t len);

  // ---- local access by the device itself (no rights, no hooks) -------------
  /// Numeric value of a row, zero-extended (sign bits kept as stored).
  uint32_t get(uint16_t row) const;
  /// Stores a numeric value into a RAM row (truncated to its size). Returns
  /// true when the stored bytes changed.
  bool set(uint16_t row, uint32_t value);
  /// Raw bytes of a RAM row (nullptr for const rows).
  uint8_t* ram(uint16_t row);
  const uint8_t* ram(uint16_t row) const;
  /// Restores defaults of every RAM row with from <= index <= to.
  void restore_defaults(uint16_t from_index, uint16_t to_index);

  /// Copies value bytes of a row into buf (local read, no rights). Returns length.
  uint16_t copy_out(uint16_t row, uint8_t* buf, uint16_t cap) const;

  // ---- change tracking --------------------------------------------------------
  /// Changes with every modification made through the OD: set() that changed
  /// a value, write(), restore_defaults(), a new node id, and every writable
  /// ram() pointer handed out (its holder may write). Code that writes the
  /// value block directly calls touch() at least when it changed an entry a
  /// PDO may map (kAttrPdo). So while the revision stays the same, every PDO
  /// configuration and every mappable value reads as before: TPDOs skip
  /// rebuilding their payload then. Wraps at 2^16.
  uint16_t revision() const { return revision_; }
  void touch() { ++revision_; }

 private:
  uint32_t default_of(const OdEntry& e) const;
  /// Current text length of a string row (RAM or flash), at most its capacity.
  uint16_t string_length(uint16_t row) const;
  /// Bytes of a numeric row's value (0 for a type without a size entry).
  MB2CO_INLINE uint8_t numeric_size(const OdEntry* e) const {
    const uint8_t type = flash_read(reinterpret_cast<const uint8_t*>(e) + kOdEntryTypeHookOffset) & 0x0F;
    return type <= kUnsigned32 ? type_bytes_[type] : static_cast<uint8_t>(0);
  }
  MB2CO_INLINE uint8_t* value_at(const OdEntry* e) const { return values_ + flash_read(&e->loc); }
  uint32_t check_limits(const OdEntry& e, const uint8_t* data, uint16_t len) const;
  void store(const OdEntry& e, const uint8_t* data, uint16_t len);

  const OdDefinition& def_;
  uint8_t* values_;
  /// Byte sizes of types 0001h–0007h, from the bit lengths in this OD's own
  /// data-type entries, read once (they are const): sizing is on every value
  /// access.
  uint8_t type_bytes_[kUnsigned32 + 1];
  OdWriteHook hook_;
  void* hook_ctx_;
  uint16_t revision_;
  uint8_t node_id_;
};

/// Little-endian helpers (the bus byte order).
inline uint16_t le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
inline uint32_t le32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
}
inline void put_le16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}
inline void put_le32(uint8_t* p, uint32_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
  p[2] = static_cast<uint8_t>(v >> 16);
  p[3] = static_cast<uint8_t>(v >> 24);
}

}  // namespace canopen
}  // namespace mb2co
