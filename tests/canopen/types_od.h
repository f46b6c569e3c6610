// A test-only OD with one entry of every CiA 301 basic data type (2101h-
// 2123h) and limited entries of the wider ones (2200h-2206h), for the OD
// core's tests (tests/canopen/test_od_types.cpp) and the EDS round trip
// (tests/eds/test_od_types_eds.cpp). Include in one .cpp per binary: it
// defines the tables.
#pragma once
#include "canopen/od.h"
#include "canopen/od_comm.h"
#include "test_od_pdos.h"

namespace mb2co {
namespace test {
namespace types {

// clang-format off
#define MB2CO_TYPES_OD(N, S)                                                                                   \
  MB2CO_OD_DATA_TYPES(N, S)                                                                                    \
  MB2CO_OD_COMM_1000(N, S, 0x12345678, "types test node", "hw", "sw", 7, 8, 9, 0)                              \
  MB2CO_TEST_OD_PDOS(N)                                                                                        \
  N(0x2101, 0, x2101_0_boolean, BOOL, RW, kAttrPdo, kHookNone, 1, "BOOLEAN")                                   \
  N(0x2102, 0, x2102_0_integer8, I8, RW, kAttrPdo, kHookNone, 0, "INTEGER8")                                   \
  N(0x2103, 0, x2103_0_integer16, I16, RW, kAttrPdo, kHookNone, 0, "INTEGER16")                                \
  N(0x2104, 0, x2104_0_integer24, I24, RW, kAttrPdo, kHookNone, 0x123456, "INTEGER24")                         \
  N(0x2105, 0, x2105_0_integer32, I32, RW, kAttrPdo, kHookNone, 0, "INTEGER32")                                \
  N(0x2106, 0, x2106_0_integer40, I40, RW, kAttrPdo, kHookNone, 0, "INTEGER40")                                \
  N(0x2107, 0, x2107_0_integer48, I48, RW, kAttrPdo, kHookNone, 0, "INTEGER48")                                \
  N(0x2108, 0, x2108_0_integer56, I56, RW, kAttrPdo, kHookNone, 0, "INTEGER56")                                \
  N(0x2109, 0, x2109_0_integer64, I64, RW, kAttrPdo, kHookNone, 0, "INTEGER64")                                \
  N(0x210A, 0, x210A_0_unsigned8, U8, RW, kAttrPdo, kHookNone, 0, "UNSIGNED8")                                 \
  N(0x210B, 0, x210B_0_unsigned16, U16, RW, kAttrPdo, kHookNone, 0, "UNSIGNED16")                              \
  N(0x210C, 0, x210C_0_unsigned24, U24, RW, kAttrPdo, kHookNone, 0, "UNSIGNED24")                              \
  N(0x210D, 0, x210D_0_unsigned32, U32, RW, kAttrPdo, kHookNone, 0, "UNSIGNED32")                              \
  N(0x210E, 0, x210E_0_unsigned40, U40, RW, kAttrPdo, kHookNone, 0, "UNSIGNED40")                              \
  N(0x210F, 0, x210F_0_unsigned48, U48, RW, kAttrPdo, kHookNone, 0, "UNSIGNED48")                              \
  N(0x2110, 0, x2110_0_unsigned56, U56, RW, kAttrPdo, kHookNone, 0, "UNSIGNED56")                              \
  N(0x2111, 0, x2111_0_unsigned64, U64, RW, kAttrPdo, kHookNone, 0xDEADBEEF, "UNSIGNED64")                     \
  N(0x2112, 0, x2112_0_real32, REAL32, RW, kAttrPdo, kHookNone, -1234.5625f, "REAL32")                         \
  N(0x2113, 0, x2113_0_real64, REAL64, RW, kAttrPdo, kHookNone, 0, "REAL64")                                   \
  N(0x2114, 0, x2114_0_timeOfDay, TIME_OF_DAY, RW, kAttrPdo, kHookNone, 0, "TIME_OF_DAY")                      \
  N(0x2115, 0, x2115_0_timeDifference, TIME_DIFFERENCE, RW, kAttrPdo, kHookNone, 0, "TIME_DIFFERENCE")         \
  S(0x2120, 0, x2120_0_visibleString, RW, kHookNone, 10, "hello", "VISIBLE_STRING")                            \
  S(0x2121, 0, x2121_0_octetString, RW, kHookNone, MB2CO_OD_OCTETS(6), "\x01\x02\x03", "OCTET_STRING")         \
  S(0x2122, 0, x2122_0_unicodeString, RW, kHookNone, MB2CO_OD_UNICODE(4), "", "UNICODE_STRING")                \
  S(0x2123, 0, x2123_0_domain, RW, kHookNone, MB2CO_OD_DOMAIN(12), "", "DOMAIN")                               \
  N(0x2200, 0, x2200_0_limitedInteger24, I24, RW, 0, kHookNone, 0, "limited INTEGER24")                        \
  N(0x2201, 0, x2201_0_limitedUnsigned40, U40, RW, 0, kHookNone, 10, "limited UNSIGNED40")                     \
  N(0x2202, 0, x2202_0_limitedInteger64, I64, RW, 0, kHookNone, 0, "limited INTEGER64")                        \
  N(0x2203, 0, x2203_0_limitedUnsigned64, U64, RW, 0, kHookNone, 10, "limited UNSIGNED64")                     \
  N(0x2204, 0, x2204_0_limitedReal32, REAL32, RW, 0, kHookNone, 0, "limited REAL32")                           \
  N(0x2205, 0, x2205_0_limitedReal64, REAL64, RW, 0, kHookNone, 0, "limited REAL64")                           \
  N(0x2206, 0, x2206_0_limitedUnsigned56, U56, RW, 0, kHookNone, 10, "limited UNSIGNED56")

// REAL64 limits -100.0 (C059000000000000h) and 100.0 (4059000000000000h).
#define MB2CO_TYPES_LIMITS(L)                                                          \
  L(0x2200, 0, -1000, 1000)                                                            \
  L(0x2201, 0, 10, 0x10000000000LL - 1000)                                             \
  L(0x2202, 0, -5000000000000LL, 5000000000000LL)                                      \
  L(0x2203, 0, 10, 1000000000000000LL)                                                 \
  L(0x2204, 0, od_real32_limit(-1.5f), od_real32_limit(2.5f))                          \
  L(0x2205, 0, od_real_limit(0xC059000000000000ULL, 8), od_real_limit(0x4059000000000000ULL, 8)) \
  L(0x2206, 0, 10, 0xFFFFFFFFFFFFFFLL - 1)
// clang-format on

namespace od {
using namespace ::mb2co::canopen;
MB2CO_OD_DECLARE(Types, MB2CO_TYPES_OD)
#define MB2CO_OD_CUR_V TypesValues
#define MB2CO_OD_CUR_P TypesStrings
MB2CO_OD_DEFINE(Types, MB2CO_TYPES_OD, MB2CO_TYPES_LIMITS, MB2CO_OD_NO_HANDLERS)
#undef MB2CO_OD_CUR_V
#undef MB2CO_OD_CUR_P
}  // namespace od

}  // namespace types
}  // namespace test
}  // namespace mb2co
