// What an I/O node may ever put on the bus, whatever it was fed: shared by the
// randomized property test (GoogleTest) and the libFuzzer target (no gtest).
// Every check reads the OD as it is at the moment the frame leaves.
#pragma once
#include <stdint.h>

#include <string>

#include "canopen/od.h"
#include "canopen/od_comm.h"
#include "canopen/sdo_abort.h"
#include "ionode/io_node.h"

namespace mb2co {
namespace test {

inline bool known_sdo_abort(uint32_t code) {
  using namespace canopen;
  switch (code) {
    case kAbortToggle:
    case kAbortTimeout:
    case kAbortCommand:
    case kAbortUnsupported:
    case kAbortWriteOnly:
    case kAbortReadOnly:
    case kAbortNoObject:
    case kAbortNotMappable:
    case kAbortMapLength:
    case kAbortIncompatible:
    case kAbortTypeMismatch:
    case kAbortTooLong:
    case kAbortTooShort:
    case kAbortNoSubindex:
    case kAbortInvalidValue:
    case kAbortValueTooHigh:
    case kAbortValueTooLow:
    case kAbortGeneral:
    case kAbortStore:
    case kAbortLocalControl:
    case kAbortDeviceState:
      return true;
    default:
      return false;
  }
}

/// True if `id` is one the node may send on now: 580h/700h + id, the valid
/// EMCY COB-ID, the SYNC COB-ID while producing, a valid TPDO's COB-ID.
inline bool node_may_send_on(ionode::IoNode& io, uint32_t id) {
  using namespace canopen;
  const ObjectDictionary& od = io.od();
  const uint8_t node_id = od.node_id();
  if (id == 0x580u + node_id || id == 0x700u + node_id) return true;
  const uint32_t emcy = od.get(od.find(0x1014, 0));
  if (!(emcy & 0x80000000u) && id == (emcy & 0x7FFu)) return true;
  const uint32_t sync = od.get(od.find(0x1005, 0));
  if ((sync & 0x40000000u) && id == (sync & 0x7FFu)) return true;
  // TIME producer (1012h bit 30), where the profile has one.
  const uint16_t time_row = od.find(0x1012, 0);
  if (time_row != ObjectDictionary::kNoRow) {
    const uint32_t time = od.get(time_row);
    if ((time & 0x40000000u) && id == (time & 0x7FFu)) return true;
  }
  for (uint16_t n = 0; n < kPdoCount; ++n) {
    const uint32_t cob = od.get(od.find(static_cast<uint16_t>(0x1800 + n), 1));
    if (!(cob & 0x80000000u) && id == (cob & 0x7FFu)) return true;
  }
  return false;
}

/// Empty if `f` (just sent by `io`) is acceptable, else what is wrong.
inline std::string frame_violation(ionode::IoNode& io, const CanFrame& f) {
  const uint8_t node_id = io.od().node_id();
  if (f.rtr() || f.extended() || f.dlc > 8) return "RTR, extended or DLC > 8";
  if (!node_may_send_on(io, f.id)) return "sent on a foreign id";
  if (f.id == 0x580u + node_id) {
    if (f.dlc != 8) return "SDO response not 8 bytes";
    if ((f.data[0] >> 5) > 4) return "SDO response with an undefined specifier";
    if (f.data[0] == 0x80 && !known_sdo_abort(canopen::le32(&f.data[4]))) return "unknown abort code";
  }
  if (f.id == 0x700u + node_id && f.dlc != 1) return "error control frame not 1 byte";
  return std::string();
}

}  // namespace test
}  // namespace mb2co
