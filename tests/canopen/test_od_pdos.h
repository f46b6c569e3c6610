// Four RPDOs and four TPDOs, disabled and unmapped (COB-IDs relative to the
// node id), for the test-only ODs: map them with Harness::map_pdo.
#pragma once
#include "canopen/od_comm.h"

// clang-format off
#define MB2CO_TEST_OD_PDOS(N)                                                                   \
  MB2CO_OD_RPDO_COMM(N, 0x1400, x1400, 0x80000200, kAttrNodeId, 255, 0, "RPDO1")                \
  MB2CO_OD_RPDO_COMM(N, 0x1401, x1401, 0x80000300, kAttrNodeId, 255, 0, "RPDO2")                \
  MB2CO_OD_RPDO_COMM(N, 0x1402, x1402, 0x80000400, kAttrNodeId, 255, 0, "RPDO3")                \
  MB2CO_OD_RPDO_COMM(N, 0x1403, x1403, 0x80000500, kAttrNodeId, 255, 0, "RPDO4")                \
  MB2CO_OD_PDO_MAP(N, 0x1600, x1600, kHookRpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "RPDO1 mapping")  \
  MB2CO_OD_PDO_MAP(N, 0x1601, x1601, kHookRpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "RPDO2 mapping")  \
  MB2CO_OD_PDO_MAP(N, 0x1602, x1602, kHookRpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "RPDO3 mapping")  \
  MB2CO_OD_PDO_MAP(N, 0x1603, x1603, kHookRpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "RPDO4 mapping")  \
  MB2CO_OD_TPDO_COMM(N, 0x1800, x1800, 0x80000180, kAttrNodeId, 255, 0, 0, "TPDO1")             \
  MB2CO_OD_TPDO_COMM(N, 0x1801, x1801, 0x80000280, kAttrNodeId, 255, 0, 0, "TPDO2")             \
  MB2CO_OD_TPDO_COMM(N, 0x1802, x1802, 0x80000380, kAttrNodeId, 255, 0, 0, "TPDO3")             \
  MB2CO_OD_TPDO_COMM(N, 0x1803, x1803, 0x80000480, kAttrNodeId, 255, 0, 0, "TPDO4")             \
  MB2CO_OD_PDO_MAP(N, 0x1A00, x1A00, kHookTpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "TPDO1 mapping")  \
  MB2CO_OD_PDO_MAP(N, 0x1A01, x1A01, kHookTpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "TPDO2 mapping")  \
  MB2CO_OD_PDO_MAP(N, 0x1A02, x1A02, kHookTpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "TPDO3 mapping")  \
  MB2CO_OD_PDO_MAP(N, 0x1A03, x1A03, kHookTpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "TPDO4 mapping")
// clang-format on
