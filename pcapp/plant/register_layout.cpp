#include "register_layout.h"

#include "canopen/od.h"
#include "gateway/gateway_od.h"
#include "gateway/register_map.h"

namespace mb2co {
namespace pcapp {

namespace {
using modbus::Table;

// Which addresses of a table are mapped (and, holding, writable), in
// address order, as the register map lays them out.
void scan_map(const canopen::ObjectDictionary& od, Table table, RegisterLayout& layout) {
  const bool holding = table == Table::kHoldingRegisters;
  std::vector<bool>& mapped = layout.mapped[holding ? 0 : 1];
  gateway::MapWalk<gateway::OdMapEntries> walk(gateway::OdMapEntries(od, table), false);
  while (walk.next()) {
    const gateway::MapItem& item = walk.item();
    bool rw = false;
    if (item.entry != 0) {
      const uint16_t target = od.find(canopen::map_index(item.entry), canopen::map_sub(item.entry));
      rw = target != canopen::ObjectDictionary::kNoRow && (od.entry(target).attr & canopen::kAttrWrite) != 0;
    }
    for (uint8_t w = 0; w < item.width; ++w) {
      mapped.push_back(item.entry != 0);
      if (holding) layout.writable.push_back(rw && item.width == 1);
    }
  }
}

// Holding registers win when an entry is mapped in both tables.
Location locate(const canopen::ObjectDictionary& od, Field field) {
  const canopen::OdKey key = field_spec(field).key();
  gateway::MapItem item = gateway::locate(od, Table::kHoldingRegisters, key);
  if (item.mapped()) return {RegTable::kHolding, item.first, item.width};
  item = gateway::locate(od, Table::kInputRegisters, key);
  if (item.mapped()) return {RegTable::kInput, item.first, item.width};
  return {};
}
}  // namespace

RegisterLayout layout_from_od(const canopen::ObjectDictionary& od) {
  RegisterLayout layout;
  scan_map(od, Table::kHoldingRegisters, layout);
  scan_map(od, Table::kInputRegisters, layout);
  for (int f = 0; f < kFieldCount; ++f) layout.at[f] = locate(od, static_cast<Field>(f));
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
