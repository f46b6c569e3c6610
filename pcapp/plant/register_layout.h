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

/// The OD entries the app uses. Values of 8/16-bit entries fit one register;
/// the latency timestamps are 32-bit (two registers, high word first).
enum class Field : uint8_t {
  inputs,          ///< 6000h/1: START, STOP, STOP2 levels (gateway::Button bits)
  run_state,       ///< 2100h/2: RUN state as the firmware decided it
  stop2_count,     ///< 2100h/3: this panel's STOP2 event counter
  stop_cause,      ///< 2100h/4: gateway::StopCause of the latched stop
  start_count,     ///< 2100h/5
  stop_count,      ///< 2100h/6
  prev_run,        ///< 2110h/1
  prev_stop2,      ///< 2110h/2
  prev_status,     ///< 2110h/3: gateway::NeighbourStatus
  next_run,        ///< 2120h/1
  next_status,     ///< 2120h/3
  leds,            ///< 2200h/0: gateway::Led bits as driven
  edge_us,         ///< 2300h/1: last button edge, firmware µs
  led_us,          ///< 2300h/2: last lab LED change, firmware µs
  remote_us,       ///< 2300h/3: last remote buttons arrival, firmware µs
  remote_buttons,  ///< 2130h/1: button levels of the watched station (by PDO)
  error_register,  ///< 1001h/0
  nmt_state,       ///< 2002h/0
  run_command,     ///< 2100h/1 (written): the PC's RUN command
  lab_led,         ///< 6200h/1 (written): bit 0 = lab LED
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
