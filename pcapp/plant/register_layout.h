// Where the gateway's Modbus registers are: the addresses of the OD entries
// the app reads and writes, taken from the maps 2400h (holding registers) and
// 2401h (input registers) of the gateway OD this app is linked with. So the
// app follows the firmware's default map by construction; tests check the
// result against docs/register-map.md.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

namespace mb2co {
namespace canopen {
class ObjectDictionary;
}

namespace pcapp {

/// The OD entries the app uses, each by its gateway::od::GatewayEntry key
/// (the firmware's name of the entry, in the comment). Values of 8/16-bit entries fit one register; the
/// latency timestamps are 32-bit (two registers, high word first).
enum class Field : uint8_t {
  inputs,          ///< x6000_1_readInput8Bit1: START, STOP, STOP2 levels (gateway::Button bits)
  run_state,       ///< x2100_2_runState: RUN state as the firmware decided it
  stop2_count,     ///< x2100_3_stop2Count: this panel's STOP2 event counter
  stop_cause,      ///< x2100_4_stopCause: gateway::StopCause of the latched stop
  start_count,     ///< x2100_5_startCount
  stop_count,      ///< x2100_6_stopCount
  prev_run,        ///< x2110_1_prevRunState
  prev_stop2,      ///< x2110_2_prevStop2Count
  prev_status,     ///< x2110_3_prevStatus: gateway::NeighbourStatus
  next_run,        ///< x2120_1_nextRunState
  next_status,     ///< x2120_3_nextStatus
  leds,            ///< x2200_0_leds: gateway::Led bits as driven
  edge_us,         ///< x2300_1_buttonEdgeUs: last button edge, firmware µs
  led_us,          ///< x2300_2_labLedUs: last lab LED change, firmware µs
  remote_us,       ///< x2300_3_remoteButtonsUs: last remote buttons arrival, firmware µs
  remote_buttons,  ///< x2130_1_remoteButtons: button levels of the watched station (by PDO)
  error_register,  ///< x1001_0_errorRegister
  nmt_state,       ///< x2002_0_nmtState
  run_command,     ///< x2100_1_runCommand (written): the PC's RUN command
  lab_led,         ///< x6200_1_writeOutput8Bit1 (written): bit 0 = lab LED
};
constexpr int kFieldCount = 20;

struct FieldSpec {
  uint16_t index;
  uint8_t sub;
  uint8_t bits;
  const char* name;  ///< for messages and the log's column names
};
const FieldSpec& field_spec(Field field);

enum class RegTable : uint8_t { none = 0, holding = 1, input = 2 };

/// Where one field is: none when neither register map holds it.
struct Location {
  RegTable table = RegTable::none;
  uint16_t address = 0;
  uint8_t width = 0;  ///< registers: 1, or 2 for a 32-bit entry
};

struct RegisterLayout {
  Location at[kFieldCount];
  /// Per table (index holding / input): true for every mapped address, in
  /// address order. Reading across a mapped address we do not need is fine;
  /// an unmapped one would be exception 02.
  std::vector<bool> mapped[2];
  /// Writable (rw OD entry) per holding address.
  std::vector<bool> writable;

  const Location& operator[](Field f) const { return at[static_cast<int>(f)]; }
};

/// Reads the maps 2400h and 2401h of a gateway OD. Holding registers win
/// when an entry is mapped in both tables (FC 17h can then reach it).
RegisterLayout layout_from_od(const canopen::ObjectDictionary& od);
/// The layout of the gateway OD's defaults (the firmware's default map).
RegisterLayout default_layout();

}  // namespace pcapp
}  // namespace mb2co
