// Turns one X-macro list of OD entries into everything that needs it: the
// RAM value block (a struct, one member per variable entry), the constant row
// table (flash on AVR), the string pool, the limits, and (host only) the names
// that the EDS and docs/od.md generators print. One definition, no drift.
//
// A list is a macro taking two macros, N for numeric entries and S for strings:
//   N(index, sub, type, access, flags, hook, default, "name")
//       type:   BOOL U8 U16 U32 I8 I16 I32
//       access: CONST (value in the row, no RAM), RO, WO, RW
//       flags:  0 or OdAttr bits (kAttrPdo, kAttrNodeId, kAttrPersist)
//   S(index, sub, access, hook, capacity, "default text", "name")
// Limits are a second list: L(index, sub, min, max).
// Rows must be written in ascending (index, sub) order: a static_assert checks.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "canopen/flash.h"
#include "canopen/od_types.h"

namespace mb2co {
namespace canopen {

/// Everything constant about one OD: tables (flash on AVR) and sizes.
struct OdDefinition {
  const OdEntry* rows;        ///< sorted by (index, sub); flash on AVR
  uint16_t row_count;
  const char* strings;        ///< default texts, NUL-separated; flash on AVR
  const OdLimit* limits;      ///< flash on AVR
  uint8_t limit_count;
  uint16_t values_size;       ///< bytes of the RAM value block
  const char* const* names;   ///< one per row; nullptr on AVR (names cost flash)
};

constexpr bool od_rows_sorted(const OdEntry* rows, uint16_t count) {
  for (uint16_t i = 1; i < count; ++i) {
    if (rows[i - 1].index > rows[i].index) return false;
    if (rows[i - 1].index == rows[i].index && rows[i - 1].sub >= rows[i].sub) return false;
  }
  return true;
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
#define MB2CO_OD_DT_BOOL ::mb2co::canopen::kBoolean
#define MB2CO_OD_DT_U8 ::mb2co::canopen::kUnsigned8
#define MB2CO_OD_DT_U16 ::mb2co::canopen::kUnsigned16
#define MB2CO_OD_DT_U32 ::mb2co::canopen::kUnsigned32
#define MB2CO_OD_DT_I8 ::mb2co::canopen::kInteger8
#define MB2CO_OD_DT_I16 ::mb2co::canopen::kInteger16
#define MB2CO_OD_DT_I32 ::mb2co::canopen::kInteger32
#define MB2CO_OD_ACC_CONST (::mb2co::canopen::kAttrRead | ::mb2co::canopen::kAttrConst)
#define MB2CO_OD_ACC_RO (::mb2co::canopen::kAttrRead | ::mb2co::canopen::kAttrRam)
#define MB2CO_OD_ACC_WO (::mb2co::canopen::kAttrWrite | ::mb2co::canopen::kAttrRam)
#define MB2CO_OD_ACC_RW \
  (::mb2co::canopen::kAttrRead | ::mb2co::canopen::kAttrWrite | ::mb2co::canopen::kAttrRam)
#define MB2CO_OD_MEMBER(index, sub) v_##index##_##sub
#define MB2CO_OD_STRMEMBER(index, sub) s_##index##_##sub

// RAM value block members: nothing for CONST rows.
#define MB2CO_OD_VAL_CONST(type, index, sub)
#define MB2CO_OD_VAL_RO(type, index, sub) MB2CO_OD_CTYPE_##type MB2CO_OD_MEMBER(index, sub);
#define MB2CO_OD_VAL_WO MB2CO_OD_VAL_RO
#define MB2CO_OD_VAL_RW MB2CO_OD_VAL_RO
#define MB2CO_OD_N_VALUE(index, sub, type, access, flags, hook, def, name) \
  MB2CO_OD_VAL_##access(type, index, sub)
#define MB2CO_OD_SVAL_CONST(index, sub, cap)
#define MB2CO_OD_SVAL_RO(index, sub, cap) char MB2CO_OD_MEMBER(index, sub)[cap];
#define MB2CO_OD_SVAL_WO MB2CO_OD_SVAL_RO
#define MB2CO_OD_SVAL_RW MB2CO_OD_SVAL_RO
#define MB2CO_OD_S_VALUE(index, sub, access, hook, cap, text, name) \
  MB2CO_OD_SVAL_##access(index, sub, cap)

// String pool members and initialisers.
#define MB2CO_OD_N_NONE(index, sub, type, access, flags, hook, def, name)
#define MB2CO_OD_S_POOL(index, sub, access, hook, cap, text, name) \
  char MB2CO_OD_STRMEMBER(index, sub)[sizeof(text)];
#define MB2CO_OD_S_POOLINIT(index, sub, access, hook, cap, text, name) text,

// Row offsets in the value block (0 for CONST rows).
#define MB2CO_OD_LOC_CONST(V, index, sub) 0
#define MB2CO_OD_LOC_RO(V, index, sub) offsetof(V, MB2CO_OD_MEMBER(index, sub))
#define MB2CO_OD_LOC_WO MB2CO_OD_LOC_RO
#define MB2CO_OD_LOC_RW MB2CO_OD_LOC_RO
// Strings: CONST capacity is the default's length.
#define MB2CO_OD_SCAP_CONST(cap, text) (sizeof(text) - 1)
#define MB2CO_OD_SCAP_RO(cap, text) (cap)
#define MB2CO_OD_SCAP_WO MB2CO_OD_SCAP_RO
#define MB2CO_OD_SCAP_RW MB2CO_OD_SCAP_RO

#define MB2CO_OD_N_ROW(V, P, index, sub, type, access, flags, hook, def, name)                \
  {index, sub, MB2CO_OD_DT_##type, hook, static_cast<uint8_t>(MB2CO_OD_ACC_##access | (flags)), \
   static_cast<uint16_t>(MB2CO_OD_LOC_##access(V, index, sub)), static_cast<uint32_t>(def)},
#define MB2CO_OD_S_ROW(V, P, index, sub, access, hook, cap, text, name)                        \
  {index, sub, ::mb2co::canopen::kVisibleString, hook,                                         \
   static_cast<uint8_t>(MB2CO_OD_ACC_##access | ::mb2co::canopen::kAttrString),                \
   static_cast<uint16_t>(MB2CO_OD_LOC_##access(V, index, sub)),                                \
   (static_cast<uint32_t>(MB2CO_OD_SCAP_##access(cap, text)) << 16) |                          \
       static_cast<uint32_t>(offsetof(P, MB2CO_OD_STRMEMBER(index, sub)))},
#define MB2CO_OD_N_NAME(index, sub, type, access, flags, hook, def, name) name,
#define MB2CO_OD_S_NAME(index, sub, access, hook, cap, text, name) name,
#define MB2CO_OD_L_ROW(index, sub, lo, hi) {index, sub, lo, hi},

// Rows refer to the value struct and string pool of the OD being defined: the
// .cpp defines MB2CO_OD_CUR_V and MB2CO_OD_CUR_P to them before MB2CO_OD_DEFINE.
#define MB2CO_OD_ROW_N(...) MB2CO_OD_N_ROW(MB2CO_OD_CUR_V, MB2CO_OD_CUR_P, __VA_ARGS__)
#define MB2CO_OD_ROW_S(...) MB2CO_OD_S_ROW(MB2CO_OD_CUR_V, MB2CO_OD_CUR_P, __VA_ARGS__)

/// In a header: the value block type `Name##Values` and the definition object.
#define MB2CO_OD_DECLARE(Name, LIST)                            \
  struct Name##Values {                                         \
    LIST(MB2CO_OD_N_VALUE, MB2CO_OD_S_VALUE)                    \
  };                                                            \
  extern const ::mb2co::canopen::OdDefinition Name##Definition;

/// In exactly one .cpp: the tables. LIMITS is a list macro taking L.
/// Define MB2CO_OD_CUR_V to Name##Values and MB2CO_OD_CUR_P to Name##Strings first.
#ifdef __AVR__
#define MB2CO_OD_NAMES_TABLE(Name, LIST)
#define MB2CO_OD_NAMES_PTR(Name) nullptr
#else
#define MB2CO_OD_NAMES_TABLE(Name, LIST) \
  static const char* const Name##Names[] = {LIST(MB2CO_OD_N_NAME, MB2CO_OD_S_NAME)};
#define MB2CO_OD_NAMES_PTR(Name) Name##Names
#endif

#define MB2CO_OD_DEFINE(Name, LIST, LIMITS)                                                     \
  struct Name##Strings {                                                                        \
    char first_; /* keeps the struct non-empty; offset 0 is never a real text */                \
    LIST(MB2CO_OD_N_NONE, MB2CO_OD_S_POOL)                                                      \
  };                                                                                            \
  static constexpr Name##Strings Name##StringPool MB2CO_FLASH = {                               \
      0, LIST(MB2CO_OD_N_NONE, MB2CO_OD_S_POOLINIT)};                                           \
  static constexpr ::mb2co::canopen::OdEntry Name##Rows[] MB2CO_FLASH = {                       \
      LIST(MB2CO_OD_ROW_N, MB2CO_OD_ROW_S)};                                                    \
  static constexpr uint16_t Name##RowCount =                                                    \
      static_cast<uint16_t>(sizeof(Name##Rows) / sizeof(Name##Rows[0]));                        \
  static_assert(::mb2co::canopen::od_rows_sorted(Name##Rows, Name##RowCount),                   \
                #Name ": OD rows must be in ascending (index, sub) order without duplicates"); \
  static constexpr ::mb2co::canopen::OdLimit Name##Limits[] MB2CO_FLASH = {                     \
      LIMITS(MB2CO_OD_L_ROW){0, 0, 0, 0}};                                                      \
  MB2CO_OD_NAMES_TABLE(Name, LIST)                                                              \
  const ::mb2co::canopen::OdDefinition Name##Definition = {                                     \
      Name##Rows,                                                                               \
      Name##RowCount,                                                                           \
      reinterpret_cast<const char*>(&Name##StringPool),                                         \
      Name##Limits,                                                                             \
      static_cast<uint8_t>(sizeof(Name##Limits) / sizeof(Name##Limits[0]) - 1),                 \
      static_cast<uint16_t>(sizeof(Name##Values)),                                              \
      MB2CO_OD_NAMES_PTR(Name)};
