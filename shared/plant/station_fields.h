// The gateway entries the PC's station reads and writes, each named once for
// every PC program (mb2co-plant, the simulator's PCs) by the firmware's own
// entry key (gateway::od::GatewayEntry, in the comment). Where a field sits
// in the Modbus tables is the register map's to say (gateway/register_map.h).
#pragma once
#include <stdint.h>

#include "canopen/od_define.h"

namespace mb2co {
namespace plant {

/// Values of 8/16-bit entries fit one register; the latency timestamps are
/// 32-bit (two registers, high word first).
enum class Field : uint8_t {
  kInputs,         ///< x6000_1_readInput8Bit1: START, STOP, STOP2 levels (gateway::Button bits)
  kRunState,       ///< x2100_2_runState: RUN state as the firmware decided it
  kStop2Count,     ///< x2100_3_stop2Count: this panel's STOP2 event counter
  kStopCause,      ///< x2100_4_stopCause: gateway::StopCause of the latched stop
  kStartCount,     ///< x2100_5_startCount
  kStopCount,      ///< x2100_6_stopCount
  kPrevRun,        ///< x2110_1_prevRunState
  kPrevStop2,      ///< x2110_2_prevStop2Count
  kPrevStatus,     ///< x2110_3_prevStatus: gateway::NeighbourStatus
  kNextRun,        ///< x2120_1_nextRunState
  kNextStatus,     ///< x2120_3_nextStatus
  kLeds,           ///< x2200_0_leds: gateway::Led bits as driven
  kEdgeUs,         ///< x2300_1_buttonEdgeUs: last button edge, firmware µs
  kLedUs,          ///< x2300_2_labLedUs: last lab LED change, firmware µs
  kRemoteUs,       ///< x2300_3_remoteButtonsUs: last remote buttons arrival, firmware µs
  kRemoteButtons,  ///< x2130_1_remoteButtons: button levels of the watched station (by PDO)
  kErrorRegister,  ///< x1001_0_errorRegister
  kNmtState,       ///< x2002_0_nmtState
  kRunCommand,     ///< x2100_1_runCommand (written): the PC's RUN command
  kLabLed,         ///< x6200_1_writeOutput8Bit1 (written): bit 0 = lab LED
};
constexpr int kFieldCount = 20;

struct FieldSpec {
  uint16_t index;
  uint8_t sub;
  uint8_t bits;
  const char* name;  ///< for messages and the log's column names
  constexpr canopen::OdKey key() const { return canopen::OdKey{index, sub, bits}; }
};
const FieldSpec& field_spec(Field field);

}  // namespace plant
}  // namespace mb2co
