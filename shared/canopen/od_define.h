// Turns one X-macro list of OD entries into everything that needs it: the
// RAM value block (a struct, one member per variable entry), the constant row
// table (flash on AVR) with the pool of distinct defaults its rows name by
// slot, the string pool, the limits, and (host only) the names
// that the EDS and docs/od.md generators print. One definition, no drift.
//
// A list is a macro taking two macros, N for numeric entries and S for strings:
//   N(index, sub, id, type, access, flags, hook, default, "name")
//       id:     the entry's identifier, x<index>_<sub>_<what it holds> in the
//               style of CANopenNode (x2100_2_runState); a static_assert
//               checks that it begins with this row's index and sub-index
//       type:   BOOL U8 U16 U24 U32 U40 U48 U56 U64 I8 I16 I24 I32 I40 I48 I56
//               I64 REAL32 REAL64 TIME_OF_DAY TIME_DIFFERENCE (od_types.h);
//               a CONST row is at most 32 bits. `default` is a number; of a
//               REAL32 row the float itself (its IEEE bits are stored); of a
//               row wider than 32 bits its low 32 bits (the rest zero).
//       access: CONST (value in the row, no RAM), RO, WO, RW
//       flags:  0 or OdAttr bits (kAttrPdo, kAttrNodeId, kAttrCommand)
//       hook:   the slot of the entry's write handler (OdHook, od_types.h;
//               kHookNone: none), whose function the OD's handler list names
//   S(index, sub, id, access, hook, capacity, "default text", "name")
//       a VISIBLE_STRING of `capacity` characters; MB2CO_OD_OCTETS(n),
//       MB2CO_OD_UNICODE(n) (n characters, 2n bytes) or MB2CO_OD_DOMAIN(n)
//       as the capacity make it an OCTET_STRING, UNICODE_STRING or DOMAIN of
//       that many bytes (OCTET_STRING and DOMAIN always have all of them).
// Limits are a second list: L(index, sub, min, max) (OdLimitValue; of a
// REAL32 entry od_real32_limit(min), od_real32_limit(max)). On the AVR a
// limited entry is at most 32 bits wide (a static_assert checks).
// Rows must be written in ascending (index, sub) order, each index from
// sub-index 0: a static_assert checks.
//
// The identifier names, for every OD `Name` (MB2CO_OD_DECLARE):
//  - the entry's member of the RAM value block `Name##Values` (the device's
//    own code reads and writes its entries there, no lookup);
//  - a constant `Name##Entry::id` (OdKey: index, sub, bits) for code that
//    reaches the entry through the OD or a map (PC app, simulator, tests).
// So one name stands for one entry in firmware, PC app and simulator. Both
// cost nothing on the AVR: member names and constexpr keys leave no trace in
// the image (the printable "name" column is host-only, see OdDefinition).
#pragma once
// The OD lists and their macros are tables, one row a line: not reflowed.
// clang-format off
#include <stddef.h>
#include <stdint.h>

#include "profiles/profile.h"
#include "platform/flash.h"
#include "canopen/od_types.h"

namespace mb2co {
namespace canopen {

/// The PDO communication and mapping records, 1400h–1BFFh, as CANopenNode's
/// and Lely's ODs keep them: arrays of one record type. Each kind (RPDO
/// communication 1400h, RPDO mapping 1600h, TPDO communication 1800h, TPDO
/// mapping 1A00h) has kOdRecordsPerKind records (PDO n at base + n) alike
/// but for their index, the place of their values and their defaults; an
/// OD keeps one template record per kind (PDO 1's rows), each row with the
/// default slots (OdRow::def_slot) of the same row of PDO 2-4 (OdRecordRow).
/// Row numbers stay those of the whole sorted list (ObjectDictionary::place()
/// finds a record row's template): the rows of PDO n + 1's record read as
/// the template's with the index + n, the value n strides further in the
/// value block, and their own default.
const uint16_t kOdRecordFirst = 0x1400;  ///< index of the first record (RPDO 1 communication)
const uint16_t kOdRecordEnd = 0x1C00;    ///< indices of records end below this
const uint8_t kOdRecordKinds = 4;        ///< kinds, 200h indices apart
const uint8_t kOdRecordsPerKind = 4;     ///< records (PDOs) of each kind, at base + 0..3

/// Where an OD's records are (compile time: MB2CO_OD_DEFINE builds the
/// tables from it).
struct OdRecordShape {
  uint16_t first;                  ///< row number of the first record row (or where it would be)
  uint16_t count;                  ///< rows of all records: kOdRecordsPerKind * sum of rows[]
  uint8_t base[kOdRecordKinds];    ///< each kind's first row, counted from `first`
  uint8_t rows[kOdRecordKinds];    ///< rows of one record of each kind (0: the OD has none)
  uint8_t stride[kOdRecordKinds];  ///< value-block bytes from one record of a kind to the next
};
/// A template row: PDO 1's row, the default slots of the same row of PDO
/// 2, 3 and 4 (PDO 1's is the row's own def_slot) and its kind's stride:
/// all a row of a record needs beyond its template row, in one place.
struct OdRecordRow {
  OdRow row;  ///< first: an OdRecordRow's address is its row's
  uint8_t more_slots[kOdRecordsPerKind - 1];
  uint8_t stride;  ///< value-block bytes from one record of its kind to the next
};
/// A record row, the k-th from OdDefinition::record_first, as stored
/// (OdRecordTable::row_templates): its template row (bits 0-5) and n for
/// PDO n + 1 (bits 6-7). One byte a row: place() finds a record row's
/// template with one read, no division.
const uint8_t kOdRecordTemplateMask = 0x3F;
const uint8_t kOdRecordNumberShift = 6;
static_assert(kOdRecordsPerKind <= 4, "n in 2 bits");
/// What find() needs of the records, in flash on AVR: where each kind's
/// rows begin (counted from OdDefinition::record_first) and how many rows a
/// record of each kind has. In OdRecordTable, the templates and the row
/// bytes follow it.
struct OdRecords {
  uint8_t base[kOdRecordKinds];
  uint8_t rows[kOdRecordKinds];
};
/// The records as stored, in flash on AVR: OdRecords, the template rows
/// (kTemplates = record_count / kOdRecordsPerKind: each kind's PDO 1
/// record, kinds in order), then one byte per record row (kRows =
/// record_count, kOdRecordTemplateMask). One table behind one pointer
/// (OdDefinition::records; the definition itself is in the Uno's RAM).
template <uint16_t kTemplates, uint16_t kRows>
struct OdRecordTable {
  OdRecords records;
  OdRecordRow templates[kTemplates > 0 ? kTemplates : 1];
  uint8_t row_templates[kRows > 0 ? kRows : 1];
};
typedef OdRecordTable<1, 1> OdRecordTableOfOne;
static_assert(offsetof(OdRecordTableOfOne, templates) == sizeof(OdRecords) && offsetof(OdRecordRow, row) == 0 &&
                  offsetof(OdRecordTableOfOne, row_templates) == sizeof(OdRecords) + sizeof(OdRecordRow),
              "the template rows follow OdRecords, the row bytes the template rows");

class HookResult;  // od.h

/// Everything constant about one OD: tables (flash on AVR) and sizes.
struct OdDefinition {
  const OdRow* rows;          ///< the rows but those of PDO records, sorted by (index, sub); flash on AVR
  uint16_t row_count;         ///< every row, those of PDO records too: the row numbers' range
  uint16_t record_first;      ///< row number of the first row of a PDO record (OdRecordShape),
  uint16_t record_count;      ///< and their number: read on every row access (RAM on the Uno)
  const OdRecords* records;   ///< the PDO records (OdRecordTable); flash on AVR
  const uint32_t* defaults;   ///< the distinct defaults >= kOdLiteralDefaults the rows name by slot; flash on AVR
  const char* strings;        ///< default texts, NUL-separated; flash on AVR
  const OdLimit* limits;      ///< flash on AVR
  uint8_t limit_count;
  uint16_t values_size;       ///< bytes of the RAM value block
  const char* const* names;   ///< one per row; nullptr on AVR (names cost flash)
  /// Calls an entry's write handler by its slot (OdRow::hook; od.h, OdHandlerCall).
  HookResult (*call_handler)(void* const* owners, uint8_t slot, bool apply, uint16_t index, uint8_t sub,
                             const uint8_t* data);
};

/// Where one OD entry is, generated for every row (`Name##Entry::id`).
/// `bits` is the value's length as a PDO or Modbus map entry names it
/// (BOOLEAN 1, others their type's width; 0 for a string).
struct OdKey {
  uint16_t index;
  uint8_t sub;
  uint8_t bits;
  /// The entry in the mapping format of 16xxh/1Axxh and 2400h-2403h.
  constexpr uint32_t map_entry() const {
    return (static_cast<uint32_t>(index) << 16) | (static_cast<uint32_t>(sub) << 8) | bits;
  }
};

/// A numeric row's index, sub-index and default (MB2CO_OD_DEFAULTS), for
/// compile-time questions about an OD's defaults on the host.
struct OdDefault {
  uint16_t index;
  uint8_t sub;
  uint32_t value;
};

/// Value-block member of a type no C type has (24/40/48/56-bit integers,
/// TIME_OF_DAY, TIME_DIFFERENCE): its bytes, little-endian as on the bus.
template <uint8_t kBytes>
struct OdRaw {
  uint8_t bytes[kBytes];
  bool operator==(const OdRaw& o) const {
    for (uint8_t i = 0; i < kBytes; ++i) {
      if (bytes[i] != o.bytes[i]) return false;
    }
    return true;
  }
  bool operator!=(const OdRaw& o) const { return !(*this == o); }
};
/// REAL64 in a value block: a double on the host; the AVR's double has 32
/// bits, so there its 8 bytes as they are.
#ifdef __AVR__
typedef OdRaw<8> OdReal64;
#else
typedef double OdReal64;
#endif

class ObjectDictionary;

/// The value of a RAM entry a PDO may map (kAttrPdo) in a value block: reads
/// as a T, but only ObjectDictionary::put() stores into it, and put() tells
/// the OD of a change (ObjectDictionary::touch), so the TPDOs see it. A plain
/// assignment does not compile: a change no TPDO notices cannot be written.
/// Same size and layout as T (the OD reaches it by byte offset); no
/// constructor, so a value block stays zero-initialised without code.
template <class T>
class PdoMapped {
 public:
  operator T() const { return value_; }

 private:
  friend class ObjectDictionary;
  T value_;
};

/// Member type of a value-block entry: PdoMapped<T> for a PDO-mappable one.
template <class T, bool kPdo>
struct OdValueOf {
  typedef T type;
};
template <class T>
struct OdValueOf<T, true> {
  typedef PdoMapped<T> type;
};

/// Alignment of the value-block member of (index, sub): a PDO record's
/// first values (sub-indices 0 and 1) where an UNSIGNED32 may start (4 on
/// the host, 1 on the AVR), so that every record of a kind has one layout
/// (od_records_uniform: a mapping record's 8-bit count would otherwise sit
/// at whatever offset the record before it left); 1 for any other entry
/// (its type's own alignment applies).
constexpr size_t od_value_align(uint16_t index, uint8_t sub) {
  return index >= kOdRecordFirst && index < kOdRecordEnd && sub <= 1 ? alignof(uint32_t) : 1;
}

/// Value of a hex digit, or 16 for none.
constexpr uint8_t od_hex_digit(char c) {
  return c >= '0' && c <= '9'   ? static_cast<uint8_t>(c - '0')
         : c >= 'A' && c <= 'F' ? static_cast<uint8_t>(c - 'A' + 10)
         : c >= 'a' && c <= 'f' ? static_cast<uint8_t>(c - 'a' + 10)
                                : static_cast<uint8_t>(16);
}

/// True when `id` reads x<index, 4 hex digits>_<sub, decimal>_<something>:
/// an identifier always says which entry it is (compile time only).
constexpr bool od_id_matches(const char* id, uint16_t index, uint8_t sub) {
  if (id[0] != 'x') return false;
  uint32_t i = 0;
  for (uint8_t k = 1; k <= 4; ++k) {
    const uint8_t d = od_hex_digit(id[k]);
    if (d > 15) return false;
    i = i * 16u + d;
  }
  if (i != index || id[5] != '_') return false;
  uint32_t s = 0;
  uint8_t k = 6;
  for (; id[k] >= '0' && id[k] <= '9'; ++k) s = s * 10u + static_cast<uint32_t>(id[k] - '0');
  return k > 6 && s == sub && id[k] == '_' && id[k + 1] != '\0';
}

/// True when the rows are sorted by (index, sub) without duplicates and
/// every index begins with sub-index 0 (CiA 301: a VAR is sub 0, an ARRAY
/// or RECORD has its highest sub-index there), so that an index's first
/// row is its sub 0 (ObjectDictionary::first_row).
constexpr bool od_rows_sorted(const OdRow* rows, uint16_t count) {
  for (uint16_t i = 0; i < count; ++i) {
    if (i == 0 || rows[i - 1].index != rows[i].index) {
      if (rows[i].sub != 0 || (i > 0 && rows[i - 1].index > rows[i].index)) return false;
    } else if (rows[i - 1].sub >= rows[i].sub) {
      return false;
    }
  }
  return true;
}

/// True when every limit names a row no wider than OdLimitValue (the
/// AVR's 32 bits: check_limits reads the value into one).
constexpr bool od_limits_fit(const OdRow* rows, uint16_t count, const OdLimit* limits, uint16_t limit_count) {
  for (uint16_t i = 0; i < limit_count; ++i) {
    for (uint16_t r = 0; r < count; ++r) {
      if (rows[r].index == limits[i].index && rows[r].sub == limits[i].sub &&
          (od_type_bit_length(rows[r].data_type()) + 7u) / 8u > sizeof(OdLimitValue)) {
        return false;
      }
    }
  }
  return true;
}

/// Kind (0 to kOdRecordKinds - 1) and PDO number (0-based: the offset from
/// its kind's base) of a record index, kOdRecordFirst..kOdRecordEnd - 1.
constexpr uint8_t od_record_kind(uint16_t index) {
  return static_cast<uint8_t>((index - kOdRecordFirst) >> 9);
}
constexpr uint16_t od_record_number(uint16_t index) {
  return static_cast<uint16_t>(index & 0x1FFu);
}

/// Where the records of the sorted `rows` are: the first row at or above
/// kOdRecordFirst, the rows below kOdRecordEnd from there, the rows of each
/// kind's first record and the distance of the value of its second record's
/// first RAM row from the same row's of the first (compile time only;
/// od_records_uniform checks the rest).
constexpr OdRecordShape od_record_shape(const OdRow* rows, uint16_t count) {
  OdRecordShape shape{0, 0, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}};
  for (uint16_t r = 0; r < count; ++r) {
    const uint16_t index = rows[r].index;
    if (index < kOdRecordFirst) {
      shape.first = static_cast<uint16_t>(r + 1);
    } else if (index < kOdRecordEnd) {
      const uint8_t kind = od_record_kind(index);
      for (uint8_t k = static_cast<uint8_t>(kind + 1); k < kOdRecordKinds; ++k) ++shape.base[k];
      ++shape.count;
      if (od_record_number(index) == 0) ++shape.rows[kind];
      if (od_record_number(index) == 1 && shape.stride[kind] == 0 && (rows[r].attr & kAttrRam)) {
        shape.stride[kind] = static_cast<uint8_t>(rows[r].loc - rows[r - shape.rows[kind]].loc);
      }
    }
  }
  return shape;
}

/// True when the rows of 1400h–1BFFh are, for each kind that has any,
/// kOdRecordsPerKind records at base + 0..3, each alike the kind's first
/// (sub-indices, types, hooks, attributes) but for the index (+ n), the
/// place of a RAM row's value (+ n strides) and the default: what
/// ObjectDictionary::place() takes them for (compile time only).
constexpr bool od_records_uniform(const OdRow* rows, uint16_t count, const OdRecordShape& shape) {
  uint16_t r = shape.first;
  for (uint8_t kind = 0; kind < kOdRecordKinds; ++kind) {
    const uint16_t first = r;
    for (uint8_t n = 0; n < kOdRecordsPerKind; ++n) {
      for (uint8_t j = 0; j < shape.rows[kind]; ++j, ++r) {
        if (r >= count) return false;
        const OdRow& t = rows[first + j];
        const OdRow& e = rows[r];
        if (e.index != kOdRecordFirst + 0x200u * kind + n || e.sub != t.sub || e.type_low != t.type_low ||
            e.type_high != t.type_high || e.hook != t.hook || e.attr != t.attr) {
          return false;
        }
        if ((e.attr & kAttrRam) && e.loc != t.loc + n * shape.stride[kind]) return false;
      }
    }
  }
  // (OdRecords counts rows in bytes; a record row's byte names its template in 6 bits)
  return r == shape.first + shape.count && shape.count <= 255 &&
         shape.count / kOdRecordsPerKind <= kOdRecordTemplateMask + 1u;
}

template <uint16_t kCount>
struct OdRowTable {
  OdRow rows[kCount > 0 ? kCount : 1];
};

/// The rows but those of the records (OdDefinition::rows; compile time).
template <uint16_t kCount>
constexpr OdRowTable<kCount> od_plain_rows(const OdRow* rows, uint16_t count, const OdRecordShape& shape) {
  OdRowTable<kCount> out{};
  uint16_t k = 0;
  for (uint16_t r = 0; r < count; ++r) {
    if (r < shape.first || r >= shape.first + shape.count) out.rows[k++] = rows[r];
  }
  return out;
}

/// The records' table (OdRecordTable) of the sorted `rows` (compile time).
template <uint16_t kTemplates, uint16_t kRows>
constexpr OdRecordTable<kTemplates, kRows> od_record_table(const OdRow* rows, const OdRecordShape& shape) {
  OdRecordTable<kTemplates, kRows> out{};
  uint16_t t = 0;  // the kind's first template row
  uint16_t k = 0;  // record rows so far
  for (uint8_t kind = 0; kind < kOdRecordKinds; ++kind) {
    const uint8_t n = shape.rows[kind];
    out.records.base[kind] = shape.base[kind];
    out.records.rows[kind] = n;
    for (uint8_t pdo = 0; pdo < kOdRecordsPerKind; ++pdo) {
      for (uint8_t j = 0; j < n; ++j, ++k) {
        OdRecordRow& tr = out.templates[t + j];
        if (pdo == 0) {
          tr.row = rows[shape.first + k];
          tr.stride = shape.stride[kind];
        } else {
          tr.more_slots[pdo - 1] = rows[shape.first + k].def_slot;
        }
        out.row_templates[k] = static_cast<uint8_t>((t + j) | (pdo << kOdRecordNumberShift));
      }
    }
    t = static_cast<uint16_t>(t + n);
  }
  return out;
}

/// The distinct defaults of the rows (OdRow::def_slot): a default below
/// kOdLiteralDefaults is in its slot itself, marked by the slot's top bit
/// (counts, bit lengths, small times: most rows); the larger defaults are
/// in a pool built at compile time from every row's default, in the order
/// of first use, and slot k (top bit clear) names the pool's value k.
const uint8_t kOdLiteralDefaults = 0x80;

template <uint16_t kCount>
struct OdDefaultPool {
  uint32_t values[kCount > 0 ? kCount : 1];
};

/// Number of distinct defaults of `count` rows that need the pool (compile
/// time only).
constexpr uint16_t od_pooled_count(const uint32_t* defaults, uint16_t count) {
  uint16_t distinct = 0;
  for (uint16_t i = 0; i < count; ++i) {
    bool seen = defaults[i] < kOdLiteralDefaults;
    for (uint16_t j = 0; j < i && !seen; ++j) seen = defaults[j] == defaults[i];
    if (!seen) ++distinct;
  }
  return distinct;
}

/// The pool of the distinct defaults from kOdLiteralDefaults up, in the
/// order of first use.
template <uint16_t kCount>
constexpr OdDefaultPool<kCount> od_default_pool(const uint32_t* defaults, uint16_t count) {
  OdDefaultPool<kCount> pool{};
  uint16_t used = 0;
  for (uint16_t i = 0; i < count; ++i) {
    bool seen = defaults[i] < kOdLiteralDefaults;
    for (uint16_t k = 0; k < used && !seen; ++k) seen = pool.values[k] == defaults[i];
    if (!seen) pool.values[used++] = defaults[i];
  }
  return pool;
}

/// Slot of `value`: the value itself when small, else its place in the
/// pool (od_default_pool of every row, which holds it).
template <uint16_t kCount>
constexpr uint8_t od_default_slot(const OdDefaultPool<kCount>& pool, uint32_t value) {
  if (value < kOdLiteralDefaults) return static_cast<uint8_t>(kOdLiteralDefaults | value);
  uint16_t k = 0;
  while (k < kCount && pool.values[k] != value) ++k;
  return static_cast<uint8_t>(k);
}

}  // namespace canopen
}  // namespace mb2co

// ---- per-column helpers ----------------------------------------------------
#define MB2CO_OD_CTYPE_BOOL uint8_t
#define MB2CO_OD_CTYPE_U8 uint8_t
#define MB2CO_OD_CTYPE_U16 uint16_t
#define MB2CO_OD_CTYPE_U32 uint32_t
#define MB2CO_OD_CTYPE_I8 int8_t
#define MB2CO_OD_CTYPE_I16 int16_t
#define MB2CO_OD_CTYPE_I32 int32_t
#define MB2CO_OD_CTYPE_U24 ::mb2co::canopen::OdRaw<3>
#define MB2CO_OD_CTYPE_U40 ::mb2co::canopen::OdRaw<5>
#define MB2CO_OD_CTYPE_U48 ::mb2co::canopen::OdRaw<6>
#define MB2CO_OD_CTYPE_U56 ::mb2co::canopen::OdRaw<7>
#define MB2CO_OD_CTYPE_U64 uint64_t
#define MB2CO_OD_CTYPE_I24 ::mb2co::canopen::OdRaw<3>
#define MB2CO_OD_CTYPE_I40 ::mb2co::canopen::OdRaw<5>
#define MB2CO_OD_CTYPE_I48 ::mb2co::canopen::OdRaw<6>
#define MB2CO_OD_CTYPE_I56 ::mb2co::canopen::OdRaw<7>
#define MB2CO_OD_CTYPE_I64 int64_t
#define MB2CO_OD_CTYPE_REAL32 float
#define MB2CO_OD_CTYPE_REAL64 ::mb2co::canopen::OdReal64
#define MB2CO_OD_CTYPE_TIME_OF_DAY ::mb2co::canopen::OdRaw<6>
#define MB2CO_OD_CTYPE_TIME_DIFFERENCE ::mb2co::canopen::OdRaw<6>
#define MB2CO_OD_DT_BOOL ::mb2co::canopen::kBoolean
#define MB2CO_OD_DT_U8 ::mb2co::canopen::kUnsigned8
#define MB2CO_OD_DT_U16 ::mb2co::canopen::kUnsigned16
#define MB2CO_OD_DT_U32 ::mb2co::canopen::kUnsigned32
#define MB2CO_OD_DT_I8 ::mb2co::canopen::kInteger8
#define MB2CO_OD_DT_I16 ::mb2co::canopen::kInteger16
#define MB2CO_OD_DT_I32 ::mb2co::canopen::kInteger32
#define MB2CO_OD_DT_U24 ::mb2co::canopen::kUnsigned24
#define MB2CO_OD_DT_U40 ::mb2co::canopen::kUnsigned40
#define MB2CO_OD_DT_U48 ::mb2co::canopen::kUnsigned48
#define MB2CO_OD_DT_U56 ::mb2co::canopen::kUnsigned56
#define MB2CO_OD_DT_U64 ::mb2co::canopen::kUnsigned64
#define MB2CO_OD_DT_I24 ::mb2co::canopen::kInteger24
#define MB2CO_OD_DT_I40 ::mb2co::canopen::kInteger40
#define MB2CO_OD_DT_I48 ::mb2co::canopen::kInteger48
#define MB2CO_OD_DT_I56 ::mb2co::canopen::kInteger56
#define MB2CO_OD_DT_I64 ::mb2co::canopen::kInteger64
#define MB2CO_OD_DT_REAL32 ::mb2co::canopen::kReal32
#define MB2CO_OD_DT_REAL64 ::mb2co::canopen::kReal64
#define MB2CO_OD_DT_TIME_OF_DAY ::mb2co::canopen::kTimeOfDay
#define MB2CO_OD_DT_TIME_DIFFERENCE ::mb2co::canopen::kTimeDifference
#define MB2CO_OD_ACC_CONST (::mb2co::canopen::kAttrRead | ::mb2co::canopen::kAttrConst)
#define MB2CO_OD_ACC_RO (::mb2co::canopen::kAttrRead | ::mb2co::canopen::kAttrRam)
#define MB2CO_OD_ACC_WO (::mb2co::canopen::kAttrWrite | ::mb2co::canopen::kAttrRam)
#define MB2CO_OD_ACC_RW \
  (::mb2co::canopen::kAttrRead | ::mb2co::canopen::kAttrWrite | ::mb2co::canopen::kAttrRam)
// Bit length as a map entry names it: BOOLEAN 1, every other its type's.
#define MB2CO_OD_BITS(type) \
  (MB2CO_OD_DT_##type == ::mb2co::canopen::kBoolean ? 1 : ::mb2co::canopen::od_type_bit_length(MB2CO_OD_DT_##type))
// A numeric row's default as its 32 stored bits: a REAL32's IEEE bits.
#define MB2CO_OD_DEFBITS(type, def)                                                                      \
  (MB2CO_OD_DT_##type == ::mb2co::canopen::kReal32 ? ::mb2co::canopen::od_real32_bits(static_cast<float>(def)) \
                                                   : static_cast<uint32_t>(def))
// The 5-bit DataType in the row's two places (OdRow).
#define MB2CO_OD_TYPE_LOW(dt) static_cast<uint8_t>((dt) & 0x0F)
#define MB2CO_OD_TYPE_HIGH(dt) static_cast<uint16_t>(((dt) >> 4) & 1)
// A string row's capacity column: bytes in bits 0-11, kind in bits 12-13.
#define MB2CO_OD_OCTETS(n) ((n) | 0x1000)
#define MB2CO_OD_UNICODE(n) ((2 * (n)) | 0x2000)
#define MB2CO_OD_DOMAIN(n) ((n) | 0x3000)
#define MB2CO_OD_CAP_BYTES(cap) ((cap) & 0x0FFF)
#define MB2CO_OD_CAP_TYPE(cap)                                                                 \
  (((cap) >> 12) == 1   ? ::mb2co::canopen::kOctetString                                      \
   : ((cap) >> 12) == 2 ? ::mb2co::canopen::kUnicodeString                                    \
   : ((cap) >> 12) == 3 ? ::mb2co::canopen::kDomain                                           \
                        : ::mb2co::canopen::kVisibleString)
// Rows that only host builds have: MB2CO_WITH_WIDE_TYPES (profiles/profile.h).

// RAM value block members, named by the identifier column: nothing for
// CONST rows; PdoMapped<T> for the PDO-mappable ones; a PDO record's first
// values aligned as od_value_align says.
#define MB2CO_OD_VAL_CONST(t, flags, id, align)
#define MB2CO_OD_VAL_RO(t, flags, id, align)                                             \
  alignas(MB2CO_OD_CTYPE_##t) alignas(align)                                              \
      ::mb2co::canopen::OdValueOf<MB2CO_OD_CTYPE_##t,                                     \
                                  (((flags) & ::mb2co::canopen::kAttrPdo) != 0)>::type id;
#define MB2CO_OD_VAL_WO MB2CO_OD_VAL_RO
#define MB2CO_OD_VAL_RW MB2CO_OD_VAL_RO
#define MB2CO_OD_N_VALUE(index, sub, id, type, access, flags, hook, def, name) \
  MB2CO_OD_VAL_##access(type, flags, id, ::mb2co::canopen::od_value_align(index, sub))
#define MB2CO_OD_SVAL_CONST(id, cap)
#define MB2CO_OD_SVAL_RO(id, cap) char id[MB2CO_OD_CAP_BYTES(cap)];
#define MB2CO_OD_SVAL_WO MB2CO_OD_SVAL_RO
#define MB2CO_OD_SVAL_RW MB2CO_OD_SVAL_RO
#define MB2CO_OD_S_VALUE(index, sub, id, access, hook, cap, text, name) \
  MB2CO_OD_SVAL_##access(id, cap)

// Entry keys (OdKey), each with the check of its identifier.
#define MB2CO_OD_KEY(index, sub, id, bits)                                  \
  constexpr ::mb2co::canopen::OdKey id = {index, sub, bits};                \
  static_assert(::mb2co::canopen::od_id_matches(#id, index, sub),           \
                #id ": an identifier begins with x<index>_<sub>_ of its row");
#define MB2CO_OD_N_KEY(index, sub, id, type, access, flags, hook, def, name)                       \
  MB2CO_OD_KEY(index, sub, id, MB2CO_OD_BITS(type))                                               \
  static_assert(sizeof(MB2CO_OD_CTYPE_##type) * 8 == (MB2CO_OD_BITS(type) + 7) / 8 * 8,           \
                #id ": its value block member has its type's size");                              \
  static_assert(MB2CO_OD_ACC_##access != MB2CO_OD_ACC_CONST || MB2CO_OD_BITS(type) <= 32,         \
                #id ": a CONST row holds at most 32 bits");
#define MB2CO_OD_S_KEY(index, sub, id, access, hook, cap, text, name) MB2CO_OD_KEY(index, sub, id, 0)

// Default table rows (numeric rows only).
#define MB2CO_OD_N_DEF(index, sub, id, type, access, flags, hook, def, name) {index, sub, MB2CO_OD_DEFBITS(type, def)},
#define MB2CO_OD_S_DEF(index, sub, id, access, hook, cap, text, name)

// String pool members and initialisers.
#define MB2CO_OD_N_NONE(index, sub, id, type, access, flags, hook, def, name)
#define MB2CO_OD_S_POOL(index, sub, id, access, hook, cap, text, name) char id[sizeof(text)];
#define MB2CO_OD_S_POOLINIT(index, sub, id, access, hook, cap, text, name) text,

// Row offsets in the value block (0 for CONST rows).
#define MB2CO_OD_LOC_CONST(V, id) 0
#define MB2CO_OD_LOC_RO(V, id) offsetof(V, id)
#define MB2CO_OD_LOC_WO MB2CO_OD_LOC_RO
#define MB2CO_OD_LOC_RW MB2CO_OD_LOC_RO
// Strings: CONST capacity is the default's length.
#define MB2CO_OD_SCAP_CONST(cap, text) (sizeof(text) - 1)
#define MB2CO_OD_SCAP_RO(cap, text) MB2CO_OD_CAP_BYTES(cap)
#define MB2CO_OD_SCAP_WO MB2CO_OD_SCAP_RO
#define MB2CO_OD_SCAP_RW MB2CO_OD_SCAP_RO

// A row's default as a 32-bit value (strings: capacity << 16 | text offset).
#define MB2CO_OD_S_DEFVAL(P, id, access, cap, text)                      \
  ((static_cast<uint32_t>(MB2CO_OD_SCAP_##access(cap, text)) << 16) |   \
   static_cast<uint32_t>(offsetof(P, id)))
#define MB2CO_OD_N_DEFAULT(P, index, sub, id, type, access, flags, hook, def, name) \
  MB2CO_OD_DEFBITS(type, def),
#define MB2CO_OD_S_DEFAULT(P, index, sub, id, access, hook, cap, text, name) \
  MB2CO_OD_S_DEFVAL(P, id, access, cap, text),
#define MB2CO_OD_N_ROW(V, P, D, index, sub, id, type, access, flags, hook, def, name)                     \
  {index, sub, MB2CO_OD_TYPE_LOW(MB2CO_OD_DT_##type), hook,                                                 \
   static_cast<uint8_t>(MB2CO_OD_ACC_##access | (flags)),                                                   \
   ::mb2co::canopen::od_default_slot(D, MB2CO_OD_DEFBITS(type, def)),                                      \
   static_cast<uint16_t>(MB2CO_OD_LOC_##access(V, id)), MB2CO_OD_TYPE_HIGH(MB2CO_OD_DT_##type)},
#define MB2CO_OD_S_ROW(V, P, D, index, sub, id, access, hook, cap, text, name)                 \
  {index, sub, MB2CO_OD_TYPE_LOW(MB2CO_OD_CAP_TYPE(cap)), hook,                                \
   static_cast<uint8_t>(MB2CO_OD_ACC_##access | ::mb2co::canopen::kAttrString),                \
   ::mb2co::canopen::od_default_slot(D, MB2CO_OD_S_DEFVAL(P, id, access, cap, text)),          \
   static_cast<uint16_t>(MB2CO_OD_LOC_##access(V, id)), 0},
#define MB2CO_OD_N_NAME(index, sub, id, type, access, flags, hook, def, name) name,
#define MB2CO_OD_S_NAME(index, sub, id, access, hook, cap, text, name) name,
#define MB2CO_OD_L_ROW(index, sub, lo, hi) {index, sub, lo, hi},

// Rows refer to the value struct and string pool of the OD being defined: the
// .cpp defines MB2CO_OD_CUR_V and MB2CO_OD_CUR_P to them before MB2CO_OD_DEFINE
// (MB2CO_OD_CUR_V is Name##Values: the default pool is named after it).
#define MB2CO_OD_PASTE2(a, b) a##b
#define MB2CO_OD_PASTE(a, b) MB2CO_OD_PASTE2(a, b)
#define MB2CO_OD_CUR_D MB2CO_OD_PASTE(MB2CO_OD_CUR_V, DefaultPool)
#define MB2CO_OD_ROW_N(...) MB2CO_OD_N_ROW(MB2CO_OD_CUR_V, MB2CO_OD_CUR_P, MB2CO_OD_CUR_D, __VA_ARGS__)
#define MB2CO_OD_ROW_S(...) MB2CO_OD_S_ROW(MB2CO_OD_CUR_V, MB2CO_OD_CUR_P, MB2CO_OD_CUR_D, __VA_ARGS__)
#define MB2CO_OD_DEFAULT_N(...) MB2CO_OD_N_DEFAULT(MB2CO_OD_CUR_P, __VA_ARGS__)
#define MB2CO_OD_DEFAULT_S(...) MB2CO_OD_S_DEFAULT(MB2CO_OD_CUR_P, __VA_ARGS__)

/// In a header: the value block type `Name##Values`, the entry keys
/// `Name##Entry::<id>` and the definition object.
#define MB2CO_OD_DECLARE(Name, LIST)                            \
  struct Name##Values {                                         \
    LIST(MB2CO_OD_N_VALUE, MB2CO_OD_S_VALUE)                    \
  };                                                            \
  namespace Name##Entry {                                       \
  LIST(MB2CO_OD_N_KEY, MB2CO_OD_S_KEY)                          \
  }                                                             \
  extern const ::mb2co::canopen::OdDefinition Name##Definition;

/// In a header, where wanted: `Name##Defaults`, the numeric rows' defaults as
/// a constexpr table (for constants derived from them at compile time; a
/// table nothing reads at run time is not in any image).
#define MB2CO_OD_DEFAULTS(Name, LIST) \
  constexpr ::mb2co::canopen::OdDefault Name##Defaults[] = {LIST(MB2CO_OD_N_DEF, MB2CO_OD_S_DEF)};

// A handler list's lines as the checks see them (od.h, OdHandlerLine), and
// as the cases of the OD's handler call (OdHandlerCall).
#define MB2CO_OD_H_LINE(slot, function, owner) {slot, owner},
// A case whose slot no row names (kNamed, od_slots_named) returns before
// the call: the compiler drops the call and the handler with it. The node's
// owner is read once, before the switch (`node`), not in each of its cases
// (40 B on each Uno image, measured).
#define MB2CO_OD_H_CASE(slot, function, owner)                                                    \
  case slot:                                                                                      \
    if ((kNamed & (1u << (slot))) == 0) break;                                                    \
    return function((owner) == ::mb2co::canopen::kOdOwnerNode ? node : owners[owner], index, sub, data, apply);
/// A HANDLERS list of an OD that has no handlers of its own.
#define MB2CO_OD_NO_HANDLERS(H)

/// In exactly one .cpp: the tables. LIMITS is a list macro taking L;
/// HANDLERS one taking H(slot, function, owner): the handlers of the
/// application's slots (kHookApp on), declared beside the OD list; the
/// node's (od_comm.h, MB2CO_OD_COMM_HANDLERS) come first in every OD. A row
/// that names a slot without a handler, or a slot named twice, does not
/// compile.
/// Define MB2CO_OD_CUR_V to Name##Values and MB2CO_OD_CUR_P to Name##Strings first.
#ifdef __AVR__
#define MB2CO_OD_NAMES_TABLE(Name, LIST)
#define MB2CO_OD_NAMES_PTR(Name) nullptr
#else
#define MB2CO_OD_NAMES_TABLE(Name, LIST) \
  static const char* const Name##Names[] = {LIST(MB2CO_OD_N_NAME, MB2CO_OD_S_NAME)};
#define MB2CO_OD_NAMES_PTR(Name) Name##Names
#endif

#define MB2CO_OD_DEFINE(Name, LIST, LIMITS, HANDLERS)                                           \
  struct Name##Strings {                                                                        \
    char first_; /* keeps the struct non-empty; offset 0 is never a real text */                \
    LIST(MB2CO_OD_N_NONE, MB2CO_OD_S_POOL)                                                      \
  };                                                                                            \
  static constexpr Name##Strings Name##StringPool MB2CO_FLASH = {                               \
      0, LIST(MB2CO_OD_N_NONE, MB2CO_OD_S_POOLINIT)};                                           \
  /* every row's default, only for the compile-time pool below (no storage) */                \
  static constexpr uint32_t Name##RowDefaults[] = {LIST(MB2CO_OD_DEFAULT_N, MB2CO_OD_DEFAULT_S)}; \
  static constexpr uint16_t Name##DefaultCount = ::mb2co::canopen::od_pooled_count(              \
      Name##RowDefaults, static_cast<uint16_t>(sizeof(Name##RowDefaults) / sizeof(uint32_t)));   \
  static_assert(Name##DefaultCount <= 256 - ::mb2co::canopen::kOdLiteralDefaults,                \
                #Name ": a row names its default by one byte");                                 \
  static constexpr ::mb2co::canopen::OdDefaultPool<Name##DefaultCount> Name##ValuesDefaultPool  \
      MB2CO_FLASH = ::mb2co::canopen::od_default_pool<Name##DefaultCount>(                      \
          Name##RowDefaults, static_cast<uint16_t>(sizeof(Name##RowDefaults) / sizeof(uint32_t))); \
  /* every row, only for the tables below (no storage) */                                     \
  static constexpr ::mb2co::canopen::OdRow Name##AllRows[] = {                                  \
      LIST(MB2CO_OD_ROW_N, MB2CO_OD_ROW_S)};                                                    \
  static constexpr uint16_t Name##RowCount =                                                    \
      static_cast<uint16_t>(sizeof(Name##AllRows) / sizeof(Name##AllRows[0]));                  \
  static_assert(::mb2co::canopen::od_rows_sorted(Name##AllRows, Name##RowCount),                \
                #Name ": OD rows in ascending (index, sub) order, no duplicates, each index from sub 0"); \
  static constexpr ::mb2co::canopen::OdRecordShape Name##RecordShape =                          \
      ::mb2co::canopen::od_record_shape(Name##AllRows, Name##RowCount);                         \
  static_assert(::mb2co::canopen::od_records_uniform(Name##AllRows, Name##RowCount,             \
                                                     Name##RecordShape),                        \
                #Name ": the PDO records (1400h-1BFFh) are 4 of each kind, alike but for index, " \
                "value place (one stride on) and default");                                     \
  static constexpr ::mb2co::canopen::OdRowTable<Name##RowCount - Name##RecordShape.count>       \
      Name##Rows MB2CO_FLASH = ::mb2co::canopen::od_plain_rows<Name##RowCount -                 \
                                                               Name##RecordShape.count>(        \
          Name##AllRows, Name##RowCount, Name##RecordShape);                                    \
  static constexpr ::mb2co::canopen::OdRecordTable<                                             \
      Name##RecordShape.count / ::mb2co::canopen::kOdRecordsPerKind, Name##RecordShape.count>  \
      Name##Records MB2CO_FLASH = ::mb2co::canopen::od_record_table<                            \
          Name##RecordShape.count / ::mb2co::canopen::kOdRecordsPerKind,                        \
          Name##RecordShape.count>(Name##AllRows, Name##RecordShape);                           \
  static_assert(sizeof(Name##Values) <= ::mb2co::canopen::kOdLocMask,                           \
                #Name ": a row's offset in the value block has 15 bits");                      \
  static constexpr ::mb2co::canopen::OdLimit Name##Limits[] MB2CO_FLASH = {                     \
      LIMITS(MB2CO_OD_L_ROW){0, 0, 0, 0}};                                                      \
  static_assert(::mb2co::canopen::od_limits_fit(Name##AllRows, Name##RowCount, Name##Limits,     \
                    static_cast<uint16_t>(sizeof(Name##Limits) / sizeof(Name##Limits[0]) - 1)), \
                #Name ": a limited entry is at most as wide as OdLimitValue");                   \
  static constexpr ::mb2co::canopen::OdHandlerLine Name##HandlerLines[] = {                   \
      MB2CO_OD_COMM_HANDLERS(MB2CO_OD_H_LINE) HANDLERS(MB2CO_OD_H_LINE)};                       \
  static_assert(::mb2co::canopen::od_handlers_distinct(Name##HandlerLines),                      \
                #Name ": every handler slot once, 1-15, with an owner slot");    \
  static ::mb2co::canopen::HookResult Name##CallHandler(void* const* owners, uint8_t slot, bool apply, \
                                                         uint16_t index, uint8_t sub, const uint8_t* data) { \
    constexpr uint16_t kNamed = ::mb2co::canopen::od_slots_named(Name##AllRows, Name##RowCount); \
    void* const node = owners[::mb2co::canopen::kOdOwnerNode];                                  \
    switch (slot) {                                                                             \
      MB2CO_OD_COMM_HANDLERS(MB2CO_OD_H_CASE)                                                   \
      HANDLERS(MB2CO_OD_H_CASE)                                                                 \
      default:                                                                                  \
        break;                                                                                  \
    }                                                                                           \
    return ::mb2co::canopen::kSdoOk;                                                            \
  }                                                                                             \
  static_assert(::mb2co::canopen::od_rows_handled(Name##AllRows, Name##RowCount, Name##HandlerLines), \
                #Name ": every slot a row names has its handler");                              \
  MB2CO_OD_NAMES_TABLE(Name, LIST)                                                              \
  const ::mb2co::canopen::OdDefinition Name##Definition = {                                     \
      Name##Rows.rows,                                                                          \
      Name##RowCount,                                                                           \
      Name##RecordShape.first,                                                                  \
      Name##RecordShape.count,                                                                  \
      &Name##Records.records,                                                                   \
      Name##ValuesDefaultPool.values,                                                           \
      reinterpret_cast<const char*>(&Name##StringPool),                                         \
      Name##Limits,                                                                             \
      static_cast<uint8_t>(sizeof(Name##Limits) / sizeof(Name##Limits[0]) - 1),                 \
      static_cast<uint16_t>(sizeof(Name##Values)),                                              \
      MB2CO_OD_NAMES_PTR(Name),                                                                 \
      &Name##CallHandler};
// clang-format on
