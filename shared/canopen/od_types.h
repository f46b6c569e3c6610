// The constant half of the Object Dictionary: one row per sub-entry, sorted by
// (index, subindex), kept in flash on the AVR. Values live in RAM elsewhere.
#pragma once
#include <stddef.h>
#include <stdint.h>

namespace mb2co {
namespace canopen {

/// CiA 301 data type indices (low byte; all we use are below 0x100). Entries
/// 0001h–0007h of every OD hold the bit length of these types, and the OD uses
/// them to size entries (seed 000 §2.2, §3.3).
enum DataType : uint8_t {
  kBoolean = 0x01,
  kInteger8 = 0x02,
  kInteger16 = 0x03,
  kInteger32 = 0x04,
  kUnsigned8 = 0x05,
  kUnsigned16 = 0x06,
  kUnsigned32 = 0x07,
  kVisibleString = 0x09,
};

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
  kAttrString = 0x80,   ///< VISIBLE_STRING; `def` low 16 bits: offset in the string pool
};

/// Which service validates and applies a write to this entry (OD write hook).
enum OdHook : uint8_t {
  kHookNone = 0,
  kHookNmt,         ///< 1017h producer heartbeat, 100Ch/100Dh guarding
  kHookHbConsumer,  ///< 1016h
  kHookEmcy,        ///< 1003h, 1014h, 1015h
  kHookSync,        ///< 1005h, 1006h, 1019h
  kHookRpdoComm,    ///< 1400h–1403h
  kHookRpdoMap,     ///< 1600h–1603h
  kHookTpdoComm,    ///< 1800h–1803h
  kHookTpdoMap,     ///< 1A00h–1A03h
  kHookStore,       ///< 1010h, 1011h
  kHookApp,         ///< application area: the application decides
};

/// One sub-entry's metadata as stored, constant, in flash on AVR (a row per
/// sub-entry makes this the largest table of an image). The 32-bit default
/// is not in the row: the rows share a pool of the distinct defaults
/// (OdDefinition::defaults; PDO mappings, COB-IDs, zeros repeat, so there
/// are far fewer than rows) and each holds its one-byte slot there, or the
/// default itself when it is small (od_define.h, kOdLiteralDefaults). The
/// same 8 bytes on both targets (the slot fills the byte before `loc`).
/// Invariant: a table of OdRow is sorted by (index, sub) with no duplicates.
struct OdRow {
  uint16_t index;
  uint8_t sub;
  uint8_t type : 4;  ///< DataType (all below 10h)
  uint8_t hook : 4;  ///< OdHook (all below 10h)
  uint8_t attr;      ///< OdAttr bits
  uint8_t def_slot;  ///< the default: OdDefinition::defaults[def_slot], or with
                     ///< the top bit set (kOdLiteralDefaults) the low 7 bits
  uint16_t loc;      ///< kAttrRam: byte offset in the value block
};
/// The byte holding `type` (low nibble: GCC allocates bit-fields from the
/// least significant bit on both targets) and `hook`, for single-field
/// reads from flash.
const uint8_t kOdEntryTypeHookOffset = 3;
static_assert(offsetof(OdRow, sub) + 1 == kOdEntryTypeHookOffset &&
                  offsetof(OdRow, attr) == kOdEntryTypeHookOffset + 1,
              "type and hook share the byte between sub and attr");
static_assert(kVisibleString < 16 && kHookApp < 16, "types and hooks fit their nibbles");

/// One sub-entry's metadata as the OD hands it out (ObjectDictionary::entry):
/// the row and its default as the 32-bit value.
struct OdEntry : OdRow {
  uint32_t def;  ///< default (const: the value itself, "stored in place");
                 ///< strings: capacity << 16 | offset of the default text in the string pool
};

/// Limits for the few entries that have them beyond their data type.
struct OdLimit {
  uint16_t index;
  uint8_t sub;
  int32_t min;
  int32_t max;
};

}  // namespace canopen
}  // namespace mb2co
