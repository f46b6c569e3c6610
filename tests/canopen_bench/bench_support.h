// Shared by the benchmark and the callgrind driver: frame building and the
// configuration of synchronous TPDOs.
#pragma once
#include "canopen/can_frame.h"
#include "canopen/od.h"
#include "canopen/od_comm.h"

namespace mb2co {
namespace bench {

inline CanFrame frame(uint32_t id, uint8_t dlc, const uint8_t* bytes) {
  CanFrame f = {};
  f.id = id;
  f.dlc = dlc;
  for (uint8_t i = 0; i < dlc; ++i) f.data[i] = bytes[i];
  return f;
}

/// Configures TPDO n (0-based) as synchronous every SYNC, mapping both input
/// bytes and the error register, by the CiA 301 procedure (disable, sub 0 =
/// 0, entries, sub 0, type, enable).
inline void make_sync_tpdo(canopen::ObjectDictionary& od, uint8_t n) {
  using canopen::put_le32;
  uint8_t b[4];
  const uint16_t comm = static_cast<uint16_t>(0x1800 + n);
  const uint16_t map = static_cast<uint16_t>(0x1A00 + n);
  put_le32(b, 0x80000000u | (0x180u + 0x100u * n + 3));
  od.write(comm, 1, b, 4);
  b[0] = 0;
  od.write(map, 0, b, 1);
  put_le32(b, MB2CO_PDO_MAP_ENTRY(0x6000, 1, 8));
  od.write(map, 1, b, 4);
  put_le32(b, MB2CO_PDO_MAP_ENTRY(0x6000, 2, 8));
  od.write(map, 2, b, 4);
  put_le32(b, MB2CO_PDO_MAP_ENTRY(0x1001, 0, 8));
  od.write(map, 3, b, 4);
  b[0] = 3;
  od.write(map, 0, b, 1);
  b[0] = 1;
  od.write(comm, 2, b, 1);
  put_le32(b, 0x180u + 0x100u * n + 3);
  od.write(comm, 1, b, 4);
}

}  // namespace bench
}  // namespace mb2co
