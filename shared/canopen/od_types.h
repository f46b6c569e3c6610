// The constant half of the Object Dictionary: one row per sub-entry, sorted by
// (index, subindex), kept in flash on the AVR. Values live in RAM elsewhere.
#pragma once
#include <stddef.h>
#include <stdint.h>

// The OD's wide extras (64-bit limits, Modbus map items wider than 32 bits
// and strings, data types 0008h-001Bh, the gateway's 2500h) are the
// profile's MB2CO_CONFIG_WIDE_TYPES (on for host builds, off on the Uno: its
// flash; the Uno's OD still knows every type's size, SDO transfer and PDO
// mapping).
#include "profiles/profile.h"

namespace mb2co {
namespace canopen {

/// CiA 301 basic data types (the index of their data-type entry, 0001h–001Bh:
/// every one is below 20h, a row holds it in 5 bits). Entries 0001h–0007h of
/// every OD (and 0008h–001Bh with MB2CO_CONFIG_WIDE_TYPES) hold their bit length
/// as UNSIGNED32 (seed 000 §2.2, §3.3); the OD sizes values by kOdTypeBytes.
enum DataType : uint8_t {
  kBoolean = 0x01,
  kInteger8 = 0x02,
  kInteger16 = 0x03,
  kInteger32 = 0x04,
  kUnsigned8 = 0x05,
  kUnsigned16 = 0x06,
  kUnsigned32 = 0x07,
  kReal32 = 0x08,
  kVisibleString = 0x09,
  kOctetString = 0x0A,
  kUnicodeString = 0x0B,
  kTimeOfDay = 0x0C,       ///< 48 bits: ms after midnight (28 bits, 4 reserved), days since 1984-01-01 (16)
  kTimeDifference = 0x0D,  ///< 48 bits: ms (28 bits, 4 reserved), days (16)
  kDomain = 0x0F,
  kInteger24 = 0x10,
  kReal64 = 0x11,
  kInteger40 = 0x12,
  kInteger48 = 0x13,
  kInteger56 = 0x14,
  kInteger64 = 0x15,
  kUnsigned24 = 0x16,
  kUnsigned40 = 0x18,
  kUnsigned48 = 0x19,
  kUnsigned56 = 0x1A,
  kUnsigned64 = 0x1B,
};
/// Data type codes a row can hold (5 bits).
const uint8_t kOdTypeCount = 0x20;
/// Bytes of the largest numeric value (64-bit types, REAL64).
const uint8_t kOdMaxNumericBytes = 8;

/// How a numeric type's bytes are compared with limits.
enum OdTypeKind : uint8_t { kKindUnsigned = 0, kKindSigned = 1, kKindReal = 2, kKindOther = 3 };
/// Kind of a data type (constexpr: host tools and compile-time checks).
constexpr OdTypeKind od_type_kind(uint8_t t) {
  return t == kInteger8 || t == kInteger16 || t == kInteger24 || t == kInteger32 ||
                 (t >= kInteger40 && t <= kInteger64)
             ? kKindSigned
         : t == kReal32 || t == kReal64 ? kKindReal
         : t == kBoolean || t == kUnsigned8 || t == kUnsigned16 || t == kUnsigned24 || t == kUnsigned32 ||
                 (t >= kUnsigned40 && t <= kUnsigned64)
             ? kKindUnsigned
             : kKindOther;
}
/// Bit length of a basic type as its data-type entry gives it (CiA 301
/// §7.4.7: strings and DOMAIN by their unit: a character, an octet, a
/// UNICODE character; 0 for a code that is no basic type).
constexpr uint8_t od_type_bit_length(uint8_t t) {
  return t == kBoolean                                                                                   ? 1
         : t == kInteger8 || t == kUnsigned8 || t == kVisibleString || t == kOctetString || t == kDomain ? 8
         : t == kInteger16 || t == kUnsigned16 || t == kUnicodeString                                    ? 16
         : t == kInteger24 || t == kUnsigned24                                                           ? 24
         : t == kInteger32 || t == kUnsigned32 || t == kReal32                                           ? 32
         : t == kInteger40 || t == kUnsigned40                                                           ? 40
         : t == kInteger48 || t == kUnsigned48 || t == kTimeOfDay || t == kTimeDifference                ? 48
         : t == kInteger56 || t == kUnsigned56                                                           ? 56
         : t == kInteger64 || t == kUnsigned64 || t == kReal64                                           ? 64
                                                                                                         : 0;
}
/// True for the types whose value is a run of bytes of the entry's own
/// capacity (rows with kAttrString): VISIBLE_STRING, OCTET_STRING,
/// UNICODE_STRING, DOMAIN.
constexpr bool od_type_is_bytes(uint8_t t) {
  return t == kVisibleString || t == kOctetString || t == kUnicodeString || t == kDomain;
}

/// Row attributes (bit set).
enum OdAttr : uint8_t {
  kAttrRead = 0x01,     ///< readable by SDO
  kAttrWrite = 0x02,    ///< writable by SDO
  kAttrConst = 0x04,    ///< never changes (EDS AccessType=const); value is in the row
  kAttrPdo = 0x08,      ///< may be mapped into a PDO
  kAttrNodeId = 0x10,   ///< default is relative to the node id (EDS $NODEID+...)
  kAttrCommand = 0x20,  ///< a command or process value, never a stored parameter:
                        ///< 1010h "save" leaves it out, every start has its default
                        ///< (RUN command, outputs, values received by RPDO)
  kAttrRam = 0x40,      ///< value lives in RAM at `loc`
  kAttrString = 0x80,   ///< a byte run (od_type_is_bytes: VISIBLE_STRING, OCTET_STRING,
                        ///< UNICODE_STRING, DOMAIN) of a capacity; `def`: capacity << 16
                        ///< | offset of the default in the string pool
};

/// The handler of an entry (OdRow::hook): its slot in the OD's table of write
/// handlers (OdDefinition::handlers, od.h's OdHandler), which validates a
/// write and applies it to the service that owns the entry, as CANopenNode's
/// OD extensions (OD_extension_t's write) and Lely's download indications do.
/// 0: no handler (the OD checks rights, size and limits, and stores). Slots
/// below kHookApp are the node's, the same in every OD (od_comm.h,
/// MB2CO_OD_COMM_HANDLERS); from kHookApp on, each device names its own
/// (gateway_od.h, io_node_od.h). A slot is a nibble of the row.
enum OdHook : uint8_t {
  kHookNone = 0,
  kHookNmt,             ///< 1017h producer heartbeat, 100Ch/100Dh guarding
  kHookHbConsumer,      ///< 1016h
  kHookEmcy,            ///< 1003h, 1014h, 1015h
  kHookSync,            ///< 1005h, 1006h, 1019h
  kHookRpdo,            ///< 1400h–1403h, 1600h–1603h
  kHookTpdo,            ///< 1800h–1803h, 1A00h–1A03h
  kHookStore,           ///< 1010h, 1011h
  kHookTimeCobId,       ///< 1012h (profile::kTime)
  kHookTimeStamp,       ///< 1013h (profile::kTime)
  kHookNodeId,          ///< the device's own node id (gateway 2000h/1, I/O node 2001h/1)
  kHookBitrate,         ///< the device's own CAN bit rate in kbit/s (2000h/2, 2001h/2)
  kHookRestartRequest,  ///< 1 reset communication, 2 reset node (gateway 2001h)
  kHookApp,             ///< the first of the application's own slots
};
/// Slots a row can name (OdRow::hook: 4 bits).
const uint8_t kOdHandlerSlots = 16;

/// One sub-entry's metadata as stored, constant, in flash on AVR (a row per
/// sub-entry makes this the largest table of an image). The 32-bit default
/// is not in the row: the rows share a pool of the distinct defaults
/// (OdDefinition::defaults; PDO mappings, COB-IDs, zeros repeat, so there
/// are far fewer than rows) and each holds its one-byte slot there, or the
/// default itself when it is small (od_define.h, kOdLiteralDefaults). The
/// same 8 bytes on both targets (the slot fills the byte before `loc`).
/// The DataType takes 5 bits: 4 beside the hook, the fifth the top bit of
/// the word of `loc` (a value block is below 32 KiB: od_define.h checks).
/// Invariant: a table of OdRow is sorted by (index, sub) with no duplicates.
struct OdRow {
  uint16_t index;
  uint8_t sub;
  uint8_t type_low : 4;    ///< DataType bits 0-3 (data_type() is the type)
  uint8_t hook : 4;        ///< OdHook: the slot of its write handler (0: none)
  uint8_t attr;            ///< OdAttr bits
  uint8_t def_slot;        ///< the default: OdDefinition::defaults[def_slot], or with
                           ///< the top bit set (kOdLiteralDefaults) the low 7 bits
  uint16_t loc : 15;       ///< kAttrRam: byte offset in the value block
  uint16_t type_high : 1;  ///< DataType bit 4 (types 10h-1Bh)
  /// The row's DataType.
  constexpr uint8_t data_type() const { return static_cast<uint8_t>(type_low | (type_high << 4)); }
};
/// The byte holding `type_low` (low nibble: GCC allocates bit-fields from
/// the least significant bit on both targets) and `hook`, and the word of
/// `loc` (bits 0-14) and `type_high` (bit 15), for single-field reads from
/// flash.
const uint8_t kOdEntryTypeHookOffset = 3;
const uint8_t kOdEntryLocOffset = 6;
const uint16_t kOdLocMask = 0x7FFF;
static_assert(offsetof(OdRow, sub) + 1 == kOdEntryTypeHookOffset &&
                  offsetof(OdRow, attr) == kOdEntryTypeHookOffset + 1 &&
                  offsetof(OdRow, def_slot) + 1 == kOdEntryLocOffset && sizeof(OdRow) == 8,
              "type and hook share the byte between sub and attr; loc is the last word");
static_assert(kUnsigned64 < kOdTypeCount && kHookApp < kOdHandlerSlots && kOdHandlerSlots == 16,
              "types fit 5 bits, handler slots a nibble");

/// One sub-entry's metadata as the OD hands it out (ObjectDictionary::entry):
/// the row and its default as the 32-bit value. `def` is the entry's own;
/// `def_slot` is the stored row's, of a PDO record's row its template's
/// (ObjectDictionary::default_slot() is the entry's).
struct OdEntry : OdRow {
  uint32_t def;  ///< default (const: the value itself, "stored in place");
                 ///< strings: capacity << 16 | offset of the default text in the string pool
};

/// A limit as stored: 64 bits with MB2CO_CONFIG_WIDE_TYPES, else 32 (the AVR:
/// no 64-bit arithmetic in its image; od_define.h refuses a limit on a
/// wider entry there). Integers: the value (an unsigned value above the
/// signed maximum is above every limit). REAL32/REAL64: the real's ordered
/// key (od_real_limit), so the check is integer-only on both targets.
/// REAL64 limits need the 64 bits: the AVR's OD has no limited REAL64.
template <bool kWide>
struct OdLimitWidth {
  typedef int64_t Value;
  typedef uint64_t Bits;
};
template <>
struct OdLimitWidth<false> {
  typedef int32_t Value;
  typedef uint32_t Bits;
};
typedef OdLimitWidth<profile::kWideTypes>::Value OdLimitValue;
typedef OdLimitWidth<profile::kWideTypes>::Bits OdLimitBits;

/// Limits for the few entries that have them beyond their data type.
struct OdLimit {
  uint16_t index;
  uint8_t sub;
  OdLimitValue min;
  OdLimitValue max;
};

/// A REAL limit as stored (OdLimit): from the IEEE bits of a real of
/// `bytes` bytes, the signed integer that orders like the real: its
/// magnitude (sign bit off), negated for a negative real. -0.0 and +0.0
/// are equal; a NaN is beyond the infinities (refused by any limit). The
/// same order as a float compare of all other values (test_od_types.cpp).
constexpr OdLimitValue od_real_limit(OdLimitBits bits, uint8_t bytes) {
  return (bits >> (8 * bytes - 1)) & 1
             ? -static_cast<OdLimitValue>(bits & ((static_cast<OdLimitBits>(1) << (8 * bytes - 1)) - 1))
             : static_cast<OdLimitValue>(bits);
}

/// The IEEE bits of a REAL limit as stored (the inverse of od_real_limit;
/// -0.0 comes back as +0.0): for tools that print limits.
constexpr OdLimitBits od_real_limit_bits(OdLimitValue key, uint8_t bytes) {
  return key < 0 ? static_cast<OdLimitBits>(static_cast<OdLimitBits>(-key) |
                                            (static_cast<OdLimitBits>(1) << (8 * bytes - 1)))
                 : static_cast<OdLimitBits>(key);
}

/// The IEEE 754 binary32 bits of `f` at compile time (a REAL32 limit or
/// default in an OD list): exact for every finite float (only exact
/// multiplications and divisions by 2). C++14 has no constexpr bit cast.
constexpr uint32_t od_real32_bits(float f) {
  uint32_t sign = 0;
  if (f < 0) {  // -0.0f reads as +0.0f (no constexpr test for it)
    sign = 0x80000000u;
    f = -f;
  }
  if (f == 0) return sign;
  int exp = 0;
  while (f >= 2.0f) {
    f /= 2.0f;
    ++exp;
  }
  while (f < 1.0f && exp > -126) {
    f *= 2.0f;
    --exp;
  }
  if (f < 1.0f) {  // subnormal: f * 2^-126, 23 fraction bits of f
    return sign | static_cast<uint32_t>(f * 8388608.0f);
  }
  return sign | (static_cast<uint32_t>(exp + 127) << 23) | (static_cast<uint32_t>((f - 1.0f) * 8388608.0f));
}
/// A REAL32 limit in an OD's limit list: L(index, sub, od_real32_limit(-1.0e6f), ...).
constexpr OdLimitValue od_real32_limit(float f) {
  return od_real_limit(od_real32_bits(f), 4);
}

}  // namespace canopen
}  // namespace mb2co
