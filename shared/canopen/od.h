// The Object Dictionary: constant rows (flash on AVR) + a caller-owned RAM
// value block. Lookup is a binary search over the sorted rows: O(log n).
// Every access from the network goes through read()/write(), which apply
// access rights, sizes, limits and the owning service's write hook, and
// answer with a CiA 301 SDO abort code (kSdoOk = done).
#pragma once
#include <stdint.h>
#include <string.h>

#include "canopen/od_define.h"
#include "canopen/od_types.h"
#include "canopen/sdo_abort.h"

namespace mb2co {
namespace canopen {

/// A write handler's decision (OdWriteHandler): store the value, take it as done
/// without storing it, or refuse it with an SDO abort code.
/// "Done, not stored" is no abort code and no bus value: write_row() answers
/// it with abort() = kSdoOk, so it never leaves the OD. It is held in the
/// 32 bits of the code (0xFFFFFFFF: not in any CiA 301 abort class) rather
/// than in a flag beside it: one 32-bit value, like the services' SdoAbort
/// results that the node's handlers pass on unchanged (a flag made it a 5-byte
/// result and grew the Uno image: docs/performance.md). Nothing outside this
/// class sees that value.
class HookResult {
 public:
  /// kSdoOk: accept, the OD stores the value; an abort code: refuse, nothing
  /// is stored. Implicit: a hook answers with the services' SdoAbort results.
  HookResult(SdoAbort abort) : code_(abort) {}  // NOLINT(google-explicit-constructor)
  /// Accepted, and the hook has done all there is to do: the value is not
  /// stored (e.g. the "save" signature of 1010h reads back as before).
  static HookResult handled() { return HookResult(static_cast<SdoAbort>(kHandled)); }

  /// True when the OD is to store the written value (accepted, not handled).
  bool store() const { return code_ == kSdoOk; }
  /// What the write answers: kSdoOk for a handled write.
  SdoAbort abort() const { return code_ == static_cast<SdoAbort>(kHandled) ? kSdoOk : code_; }

 private:
  static const uint32_t kHandled = 0xFFFFFFFFu;
  SdoAbort code_;
};

/// An entry's write handler: validates a write before it is stored and
/// applies it to the service that owns the entry, as CANopenNode's OD
/// extensions (OD_extension_t's write) and Lely's download indications do.
/// `owner` is the object bound to the handler's owner slot
/// (ObjectDictionary::set_owner), `data` the new value, little-endian as on
/// the bus, of the entry's size (checked before, with rights and limits).
/// Returns kSdoOk to accept (the OD stores the value), HookResult::handled()
/// when the handler has done all there is to do, or an SDO abort code to
/// refuse (nothing is stored). `apply` false: the check step of a request of
/// several entries (Modbus FC 0Fh/10h/17h): decide exactly as with `apply`
/// true, but carry out nothing (no save, no reset, no latch cleared, no
/// service state changed), so that a request refused at its last entry
/// leaves every observable state as it was.
typedef HookResult OdWriteFunction(void* owner, uint16_t index, uint8_t sub, const uint8_t* data, bool apply);

/// Owner slots of an OD's handlers (ObjectDictionary::set_owner): the node
/// (kOdOwnerNode: the communication area's handlers), and up to two objects
/// of the device's (its application, a part of it such as a register bank).
const uint8_t kOdOwnerNode = 0;
const uint8_t kOdOwners = 3;

/// Calls the handler of slot `slot` (OdRow::hook) with its owner
/// (owners[0..kOdOwners), bound: ObjectDictionary::set_owner). MB2CO_OD_DEFINE generates it from the OD's
/// handler list as one switch over the slots, each case a direct call of the slot's function: on the AVR the
/// compiler's jump table in flash, every handler inlined into it (a flash table of function pointers, one
/// out-of-line function per handler, measured 0.35 KB more: docs/performance.md). `apply` comes before the
/// entry (not last, as in OdWriteFunction): so avr-gcc keeps the switch's values in one run of saved
/// registers and saves them through -mcall-prologues' shared helpers (the I/O node's switch 150 B smaller,
/// measured).
typedef HookResult (*OdHandlerCall)(void* const* owners, uint8_t slot, bool apply, uint16_t index,
                                    uint8_t sub, const uint8_t* data);

/// One line of a handler list (MB2CO_OD_DEFINE's HANDLERS, od_comm.h's
/// MB2CO_OD_COMM_HANDLERS) as the compile-time checks see it: slot and owner.
struct OdHandlerLine {
  uint8_t slot;
  uint8_t owner;
};
/// True when every slot of a list is named once, none is 0, every one fits
/// a row's nibble and every owner is an owner slot (compile time).
template <size_t kLines>
constexpr bool od_handlers_distinct(const OdHandlerLine (&lines)[kLines]) {
  for (size_t i = 0; i < kLines; ++i) {
    if (lines[i].slot == kHookNone || lines[i].slot >= kOdHandlerSlots || lines[i].owner >= kOdOwners)
      return false;
    for (size_t j = 0; j < i; ++j) {
      if (lines[j].slot == lines[i].slot) return false;
    }
  }
  return true;
}
/// True when every row that names a slot finds a line of the list for it
/// (compile time).
template <size_t kLines>
constexpr bool od_rows_handled(const OdRow* rows, uint16_t count, const OdHandlerLine (&lines)[kLines]) {
  for (uint16_t r = 0; r < count; ++r) {
    bool found = rows[r].hook == kHookNone;
    for (size_t i = 0; i < kLines && !found; ++i) found = lines[i].slot == rows[r].hook;
    if (!found) return false;
  }
  return true;
}

/// The slots the rows name, bit `slot` set for each (compile time): the
/// handler call has a case only for these, so a handler of the node's list
/// that no row of this OD names (the I/O node's restart request, TIME where
/// the profile has none) costs its image nothing.
constexpr uint16_t od_slots_named(const OdRow* rows, uint16_t count) {
  uint16_t slots = 0;
  for (uint16_t r = 0; r < count; ++r) slots = static_cast<uint16_t>(slots | (1u << rows[r].hook));
  return static_cast<uint16_t>(slots & ~(1u << kHookNone));
}

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
  /// Binds the object the handlers of owner slot `owner` (< kOdOwners) are
  /// called with. The node binds kOdOwnerNode, and handlers are called only
  /// then (an OD without its node checks rights, size and limits and
  /// stores): a device that binds its node binds its own owners as well,
  /// before the first write (Gateway, IoNode: in their constructors).
  void set_owner(uint8_t owner, void* object) { owners_[owner] = object; }
  const OdDefinition& definition() const { return def_; }

  // ---- lookup ---------------------------------------------------------------
  /// Row number of (index, sub), or kNoRow. With MB2CO_CONFIG_OD_DIRECT_GET
  /// the answers are remembered (found_): find() then writes the OD's own
  /// memory, so two threads must not call it on one OD at once.
  uint16_t find(uint16_t index, uint8_t sub) const;
  /// Row of a generated entry key (`Name##Entry::x2100_2_runState`), or kNoRow.
  uint16_t find(OdKey key) const { return find(key.index, key.sub); }
  /// True when some sub-entry of `index` exists.
  bool has_index(uint16_t index) const;
  /// rows[i] = find(indices[i], 0) for `count` indices from a MB2CO_FLASH
  /// table: the services' start-up lookups as one loop.
  void find_rows(const uint16_t* indices, uint8_t count, uint16_t* rows) const;
  /// First row of `index`, its sub 0 (kNoRow if absent); rows of one index
  /// are contiguous.
  uint16_t first_row(uint16_t index) const;
  uint16_t row_count() const { return def_.row_count; }
  /// A row's metadata, decoded (from flash on AVR). Hot paths read single
  /// fields instead (attr(), index_of(), ...).
  OdEntry entry(uint16_t row) const;
  /// Single fields of a row (OdAttr bits, index, sub-index); on hosts from
  /// the direct table (below the class).
  uint8_t attr(uint16_t row) const;
  uint16_t index_of(uint16_t row) const;
  uint8_t sub_of(uint16_t row) const;
  /// Handler slot of a row (OdHook; kHookNone: no handler validates writes to it).
  MB2CO_INLINE uint8_t hook_of(uint16_t row) const {
    return static_cast<uint8_t>(
        flash_read(reinterpret_cast<const uint8_t*>(place(row).row) + kOdEntryTypeHookOffset) >> 4);
  }
  /// A row's default as a value: a node-id-relative one (kAttrNodeId) with
  /// the node id in force added, as restore_defaults() stores it.
  uint32_t default_value(uint16_t row) const { return constant_at(place(row)); }
  /// The slot that names a row's default (OdRow::def_slot: a literal with
  /// kOdLiteralDefaults set, else a place in OdDefinition::defaults).
  uint8_t default_slot(uint16_t row) const { return flash_read(slot_at(place(row))); }
  /// Bit length of a data type, read from its data-type entry (0001h–001Fh)
  /// of this very OD (0 when the OD has no such entry): what a dummy
  /// mapping entry must name.
  uint8_t type_bits(uint8_t type) const;
  /// DataType of a row (5 bits: od_types.h).
  uint8_t type_of(uint16_t row) const { return row_type(place(row).row); }
  /// Current size in bytes: numeric types from their data-type entry, strings
  /// their current text length.
  uint16_t size_of(uint16_t row) const;
  /// Bytes a write may carry at most (strings: capacity).
  uint16_t capacity_of(uint16_t row) const;

  // ---- network access (rights, sizes, limits, hooks) ------------------------
  /// Reads (index, sub) into buf (cap bytes); *len = bytes.
  SdoAbort read(uint16_t index, uint8_t sub, uint8_t* buf, uint16_t cap, uint16_t* len) const;
  /// Checks what a read would answer without copying; *row = the row.
  SdoAbort check_read(uint16_t index, uint8_t sub, uint16_t* row) const;
  /// Checks rights of a write before data arrives (segmented download).
  SdoAbort check_write(uint16_t index, uint8_t sub, uint16_t* row) const;
  /// Writes (index, sub) from data/len: rights, size, limits, the entry's
  /// handler, then store.
  SdoAbort write(uint16_t index, uint8_t sub, const uint8_t* data, uint16_t len);
  /// write() of a row whose access rights the caller has checked (a mapped
  /// RPDO entry): size, limits, the entry's handler, then store. With `apply` false only
  /// the decision (the handler checks, OdWriteHandler): the value is stored without
  /// a revision change, for the caller to check later entries of the same
  /// request against and then put back (ram_untracked).
  SdoAbort write_row(uint16_t row, const uint8_t* data, uint16_t len, bool apply = true);

  /// True when `len` bytes of `data` are a value the row's data type and
  /// limits allow (what write_row() checks before hooks): for values that
  /// enter without the write path, e.g. loaded parameters.
  bool value_allowed(uint16_t row, const uint8_t* data, uint16_t len) const {
    return check_limits(entry(row), data, len) == kSdoOk;
  }

  // ---- local access by the device itself (no rights, no hooks) -------------
  /// Numeric value of a row, zero-extended (sign bits kept as stored); of a
  /// row wider than 32 bits the low 32 bits (copy_out() has all of them).
  uint32_t get(uint16_t row) const;
  /// Stores a numeric value into a RAM row (truncated to its size; a row
  /// wider than 32 bits gets zeros above them). Returns true when the
  /// stored bytes changed.
  bool set(uint16_t row, uint32_t value);
  /// Raw bytes of a RAM row (nullptr for const rows).
  uint8_t* ram(uint16_t row);
  const uint8_t* ram(uint16_t row) const;
  /// ram() without a revision change: for an undo log that puts back exactly
  /// the bytes it saved (nothing observable changes), and for saved
  /// parameters loaded at a reset (restore_defaults() has just changed it).
  uint8_t* ram_untracked(uint16_t row) {
    return const_cast<uint8_t*>(static_cast<const ObjectDictionary*>(this)->ram(row));
  }
  /// Stores `value` into a PDO-mappable entry of a value block (the only way
  /// to: PdoMapped, od_define.h) and, when the entry changed, tells the TPDOs
  /// (touch()): a change of a mappable value cannot miss them.
  template <class T, class V>
  void put(PdoMapped<T>& entry, V value) {
    put_value(entry, static_cast<T>(value));
  }
  /// Restores defaults of every RAM row with from <= index <= to.
  void restore_defaults(uint16_t from_index, uint16_t to_index);

  /// Copies value bytes of a row into buf (local read, no rights). Returns length.
  uint16_t copy_out(uint16_t row, uint8_t* buf, uint16_t cap) const;

  // ---- change tracking --------------------------------------------------------
  /// Changes with every modification made through the OD: set() that changed
  /// a value, write(), restore_defaults(), a new node id, and every writable
  /// ram() pointer handed out (its holder may write), and put(): an entry a
  /// PDO may map (kAttrPdo) is a PdoMapped member of the value block, which
  /// only put() can store into. So while the revision stays the same, every PDO
  /// configuration and every mappable value reads as before: TPDOs skip
  /// rebuilding their payload then. Wraps at 2^16.
  uint16_t revision() const { return revision_; }
  void touch() { ++revision_; }

 private:
  /// put() after the conversion. Bytes, the most frequent, share one
  /// out-of-line copy (the Uno's flash); wider entries are stored inline.
  __attribute__((noinline)) void put_value(PdoMapped<uint8_t>& entry, uint8_t value);
  template <class T>
  void put_value(PdoMapped<T>& entry, T value) {
    if (entry.value_ == value) return;
    entry.value_ = value;
    touch();
  }
  /// Where a row's metadata is. Every read of a row goes through place(),
  /// the one place that knows the PDO records are kept as one template
  /// record per kind (od_define.h, OdRecords): a row of PDO n + 1's record
  /// reads as its kind's template row with n added to the index, n strides
  /// to `loc`, and its default in its own slot (slot_at); any other row as
  /// itself (n = 0). 4 bytes: returned in registers on the AVR (a 6- or
  /// 7-byte struct goes through the stack there, 8 bytes through pairs).
  struct Place {
    const OdRow* row;  ///< flash: the row, or its record's template row
    uint8_t n;         ///< of a record row its PDO number - 1, else 0
    uint8_t stride;    ///< of a record row its kind's (OdRecordRow::stride)
  };
  __attribute__((noinline)) Place place(uint16_t row) const;
  /// Flash address of a row's default slot: its own, or for PDO 2-4's
  /// record rows one of its template's (OdRecordRow).
  MB2CO_INLINE static const uint8_t* slot_at(Place p) {
    return p.n == 0 ? &p.row->def_slot : &reinterpret_cast<const OdRecordRow*>(p.row)->more_slots[p.n - 1];
  }
  /// find() of an index in 1400h–1BFFh, the records' (not in def_.rows).
  uint16_t find_record(uint16_t index, uint8_t sub) const;
  /// The row's 32-bit default from the pool (OdRow::def_slot). Out of line:
  /// six callers, the two reads each would cost more inline on the AVR.
  __attribute__((noinline)) uint32_t def_at(Place p) const;
  /// A row's default as a value: node-id-relative ones with the node id
  /// added (a constant row's value, a restored RAM row's). Out of line:
  /// get()'s numeric path then holds nothing across a call (no register
  /// saves on the AVR).
  __attribute__((noinline)) uint32_t constant_at(Place p) const;
  /// Current text length of a string row (RAM or flash), at most its capacity.
  uint16_t string_length(Place p) const;
  /// The word of `loc` and `type_high` (od_types.h), read from flash.
  MB2CO_INLINE static uint16_t loc_word(const OdRow* e) {
    return flash_read(
        reinterpret_cast<const uint16_t*>(reinterpret_cast<const uint8_t*>(e) + kOdEntryLocOffset));
  }
  /// DataType of a row (its 5 bits from two bytes of flash).
  static uint8_t row_type(const OdRow* e);
  /// Bytes of a numeric row's value (kOdTypeInfo; 0 for a byte-run type).
  uint8_t numeric_size(const OdRow* e) const;
  /// A RAM row's value (od_records_uniform: PDO n + 1's n strides on).
  MB2CO_INLINE uint8_t* value_at(Place p) const {
    return values_ + (loc_word(p.row) & kOdLocMask) + p.n * p.stride;
  }
  SdoAbort check_limits(const OdEntry& e, const uint8_t* data, uint16_t len) const;
  /// Copies a value into its row; `tracked` false: no revision change (a
  /// check step's value, put back before anything reads it).
  void store(const OdEntry& e, const uint8_t* data, uint16_t len, bool tracked);

  const OdDefinition& def_;
  uint8_t* values_;
  uint16_t revision_;
  uint8_t node_id_;
  void* owners_[kOdOwners];  ///< set_owner(); null: not bound
#if MB2CO_CONFIG_OD_DIRECT_GET
  // Profiles with MB2CO_CONFIG_OD_DIRECT_GET (the hosts': the simulator
  // runs every station's core on every pass; the Uno's keep their RAM and
  // flash as they are, profiles/profile.h refuses it there): each row's
  // fields that the hot paths read, and where get() finds a numeric RAM
  // row's value, resolved once at construction from the constant rows, so
  // these skip place() and the type decoding. None of it changes after
  // construction (rows, types and the value layout are constant; the node
  // id changes constants' values, which get() decodes, not these fields).
  struct Direct {
    uint32_t mask;    ///< a numeric RAM row of 1..4 bytes read as 4: its width's bits; 0: get() decodes
    uint16_t offset;  ///< of the value in values_ (with a mask)
    uint16_t index;   ///< index_of()
    uint8_t sub;      ///< sub_of()
    uint8_t attr;     ///< attr()
    uint8_t numeric;  ///< size_of() and capacity_of() of a number (numeric_size); 0: decoded
  };
  static const uint16_t kDirectRows = 1024;  ///< rows beyond this decode (no OD here has as many)
  Direct direct_[kDirectRows];
  uint16_t direct_rows_;  ///< rows of direct_ filled: the OD's, at most kDirectRows
  void resolve_direct();
  /// get() of a row not in the direct table: its decoding.
  uint32_t decoded(uint16_t row) const;
  /// index_of() of a row beyond the direct table.
  uint16_t decoded_index(uint16_t row) const;
  /// find()'s binary search (and the records' walk).
  uint16_t search(uint16_t index, uint8_t sub) const;
  /// find()'s answers, by a hash of (index, sub): rows never move, so an
  /// answer (kNoRow too) stays true for the OD's life; a slot holds the last
  /// key that hashed to it. `key` is (index << 8 | sub) + 1, 0: empty.
  struct Found {
    uint32_t key;
    uint16_t row;
  };
  static const uint16_t kFoundSlots = 256;
  mutable Found found_[kFoundSlots];
#endif
};

MB2CO_INLINE uint8_t ObjectDictionary::attr(uint16_t row) const {
#if MB2CO_CONFIG_OD_DIRECT_GET
  if (row < direct_rows_) return direct_[row].attr;
#endif
  return flash_read(&place(row).row->attr);
}

MB2CO_INLINE uint8_t ObjectDictionary::sub_of(uint16_t row) const {
#if MB2CO_CONFIG_OD_DIRECT_GET
  if (row < direct_rows_) return direct_[row].sub;
#endif
  return flash_read(&place(row).row->sub);
}

#if MB2CO_CONFIG_OD_DIRECT_GET
// On the Uno both are out of line in od.cpp (the decoding alone).
MB2CO_INLINE uint16_t ObjectDictionary::index_of(uint16_t row) const {
  return row < direct_rows_ ? direct_[row].index : decoded_index(row);
}

MB2CO_INLINE uint32_t ObjectDictionary::get(uint16_t row) const {
  // A numeric RAM row of 1-4 bytes: one 4-byte load masked to its width
  // (little-endian: od.cpp checks), inline at every caller. The bytes beyond
  // a narrow value are the next values' (a row whose load would pass the
  // block's end has mask 0 and is decoded).
  if (row < kDirectRows) {
    const Direct& d = direct_[row];
    if (d.mask != 0) {
      uint32_t v;
      memcpy(&v, values_ + d.offset, 4);
      return v & d.mask;
    }
  }
  return decoded(row);
}
#endif

/// Little-endian helpers (the bus byte order).
inline uint16_t le16(const uint8_t* p) {
  return static_cast<uint16_t>(p[0] | (p[1] << 8));
}
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
