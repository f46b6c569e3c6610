#include "register_layout.h"

#include "canopen/od.h"
#include "gateway/gateway_od.h"

namespace mb2co {
namespace pcapp {

namespace {
const FieldSpec kSpecs[kFieldCount] = {
    {0x6000, 1, 8, "inputs"},        {0x2100, 2, 8, "run_state"},     {0x2100, 3, 16, "stop2_count"},
    {0x2100, 4, 8, "stop_cause"},    {0x2100, 5, 16, "start_count"},  {0x2100, 6, 16, "stop_count"},
    {0x2110, 1, 8, "prev_run"},      {0x2110, 2, 16, "prev_stop2"},   {0x2110, 3, 8, "prev_status"},
    {0x2120, 1, 8, "next_run"},      {0x2120, 3, 8, "next_status"},   {0x2200, 0, 8, "leds"},
    {0x2300, 1, 32, "edge_us"},      {0x2300, 2, 32, "led_us"},       {0x2300, 3, 32, "remote_us"},
    {0x2130, 1, 8, "remote_buttons"}, {0x1001, 0, 8, "error_register"}, {0x2002, 0, 8, "nmt_state"},
    {0x2100, 1, 8, "run_command"},   {0x6200, 1, 8, "lab_led"},
};

void scan_map(const canopen::ObjectDictionary& od, uint16_t map_index, RegTable table, RegisterLayout& layout) {
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
    const uint8_t width = bits == 32 ? 2 : 1;
    bool rw = false;
    if (entry != 0) {
      const uint16_t target = od.find(index, sub);
      rw = target != canopen::ObjectDictionary::kNoRow && (od.entry(target).attr & canopen::kAttrWrite) != 0;
    }
    for (int f = 0; f < kFieldCount; ++f) {
      const FieldSpec& s = kSpecs[f];
      Location& at = layout.at[f];
      const bool better = at.table == RegTable::none || (table == RegTable::holding && at.table != RegTable::holding);
      if (entry != 0 && s.index == index && s.sub == sub && s.bits == bits && better) at = {table, address, width};
    }
    for (uint8_t w = 0; w < width; ++w) {
      mapped.push_back(entry != 0);
      if (table == RegTable::holding) layout.writable.push_back(rw && width == 1);
    }
    address = static_cast<uint16_t>(address + width);
  }
}
}  // namespace

const FieldSpec& field_spec(Field field) { return kSpecs[static_cast<int>(field)]; }

RegisterLayout layout_from_od(const canopen::ObjectDictionary& od) {
  RegisterLayout layout;
  scan_map(od, 0x2400, RegTable::holding, layout);
  scan_map(od, 0x2401, RegTable::input, layout);
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
