#include "register_layout.h"

#include "canopen/od.h"
#include "gateway/gateway_od.h"

namespace mb2co {
namespace pcapp {

namespace {
// Index, sub-index and width come from the OD's own entry keys (the names
// the firmware uses for the same entries); the names are the log's columns.
constexpr FieldSpec spec(canopen::OdKey key, const char* name) {
  return {key.index, key.sub, key.bits, name};
}
namespace e = gateway::od::GatewayEntry;
const FieldSpec kSpecs[kFieldCount] = {
    spec(e::x6000_1_readInput8Bit1, "inputs"),        spec(e::x2100_2_runState, "run_state"),
    spec(e::x2100_3_stop2Count, "stop2_count"),       spec(e::x2100_4_stopCause, "stop_cause"),
    spec(e::x2100_5_startCount, "start_count"),       spec(e::x2100_6_stopCount, "stop_count"),
    spec(e::x2110_1_prevRunState, "prev_run"),        spec(e::x2110_2_prevStop2Count, "prev_stop2"),
    spec(e::x2110_3_prevStatus, "prev_status"),       spec(e::x2120_1_nextRunState, "next_run"),
    spec(e::x2120_3_nextStatus, "next_status"),       spec(e::x2200_0_leds, "leds"),
    spec(e::x2300_1_buttonEdgeUs, "edge_us"),         spec(e::x2300_2_labLedUs, "led_us"),
    spec(e::x2300_3_remoteButtonsUs, "remote_us"),    spec(e::x2130_1_remoteButtons, "remote_buttons"),
    spec(e::x1001_0_errorRegister, "error_register"), spec(e::x2002_0_nmtState, "nmt_state"),
    spec(e::x2100_1_runCommand, "run_command"),       spec(e::x6200_1_writeOutput8Bit1, "lab_led"),
};

void scan_map(const canopen::ObjectDictionary& od, uint16_t map_index, RegTable table,
              RegisterLayout& layout) {
  const uint16_t row0 = od.find(map_index, 0);
  if (row0 == canopen::ObjectDictionary::kNoRow) return;
  const uint32_t count = od.get(row0);
  std::vector<bool>& mapped = layout.mapped[table == RegTable::holding ? 0 : 1];
  uint16_t address = 0;
  for (uint32_t k = 1; k <= count; ++k) {
    const uint16_t row = static_cast<uint16_t>(row0 + k);
    if (od.find(map_index, static_cast<uint8_t>(k)) != row) break;  // beyond the map's capacity
    const uint32_t entry = od.get(row);
    const uint16_t index = static_cast<uint16_t>(entry >> 16);
    const uint8_t sub = static_cast<uint8_t>(entry >> 8);
    const uint8_t bits = static_cast<uint8_t>(entry);
    // One register per 16 bits, as the gateway lays them out (OdRegisterBank).
    const uint8_t width = static_cast<uint8_t>(entry != 0 && bits > 16 ? (bits + 15) / 16 : 1);
    bool rw = false;
    if (entry != 0) {
      const uint16_t target = od.find(index, sub);
      rw = target != canopen::ObjectDictionary::kNoRow && (od.entry(target).attr & canopen::kAttrWrite) != 0;
    }
    for (int f = 0; f < kFieldCount; ++f) {
      const FieldSpec& s = kSpecs[f];
      Location& at = layout.at[f];
      const bool better =
          at.table == RegTable::none || (table == RegTable::holding && at.table != RegTable::holding);
      if (entry != 0 && s.index == index && s.sub == sub && s.bits == bits && better)
        at = {table, address, width};
    }
    for (uint8_t w = 0; w < width; ++w) {
      mapped.push_back(entry != 0);
      if (table == RegTable::holding) layout.writable.push_back(rw && width == 1);
    }
    address = static_cast<uint16_t>(address + width);
  }
}
}  // namespace

const FieldSpec& field_spec(Field field) {
  return kSpecs[static_cast<int>(field)];
}

RegisterLayout layout_from_od(const canopen::ObjectDictionary& od) {
  RegisterLayout layout;
  scan_map(od, e::x2400_0_holdingMapCount.index, RegTable::holding, layout);
  scan_map(od, e::x2401_0_inputMapCount.index, RegTable::input, layout);
  return layout;
}

RegisterLayout default_layout() {
  static gateway::od::GatewayValues values;  // large: not on the stack
  canopen::ObjectDictionary od(gateway::od::GatewayDefinition, reinterpret_cast<uint8_t*>(&values));
  od.restore_defaults(0x0000, 0xFFFF);
  return layout_from_od(od);
}

}  // namespace pcapp
}  // namespace mb2co
