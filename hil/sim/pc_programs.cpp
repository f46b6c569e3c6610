#include "sim/pc_programs.h"

#include <algorithm>
#include <stdexcept>

#include "gateway/gateway_od.h"
#include "modbus/protocol.h"

namespace mb2co {
namespace sim {
namespace {

using modbus::Table;
using plant::Field;

uint16_t address_of(Table table, canopen::OdKey key) {
  const gateway::MapItem item = gateway::default_location(table, key);
  if (!item.mapped()) throw std::logic_error("the PC programs' entry is not in the default map");
  return item.first;
}

PcRegisters locate_pc_registers() {
  PcRegisters r{};
  for (int f = 0; f < plant::kFieldCount; ++f) {
    r.input[f] =
        gateway::default_location(Table::kInputRegisters, plant::field_spec(static_cast<Field>(f)).key());
  }
  uint32_t first = 0xFFFF;
  uint32_t end = 0;
  for (const Field f : plant::kStationReads) {
    const gateway::MapItem& item = r.input[static_cast<int>(f)];
    if (!item.mapped()) throw std::logic_error("a station field is not an input register of the default map");
    first = std::min<uint32_t>(first, item.first);
    end = std::max<uint32_t>(end, item.first + item.width);
  }
  r.station_first = static_cast<uint16_t>(first);
  r.station_count = static_cast<uint16_t>(end - first);
  r.run_command = address_of(Table::kHoldingRegisters, plant::field_spec(Field::kRunCommand).key());
  r.remote_buttons = r.input[static_cast<int>(Field::kRemoteButtons)].first;
  r.start = address_of(Table::kDiscreteInputs, gateway::od::GatewayEntry::x2140_1_startPressed);
  r.lab_led = address_of(Table::kCoils, plant::field_spec(Field::kLabLed).key());
  return r;
}

}  // namespace

const PcRegisters& pc_registers() {
  static const PcRegisters registers = locate_pc_registers();
  return registers;
}

PlantProgram::PlantProgram(const plant::PlantConfig& config, uint8_t modbus_address, uint32_t lost_after)
    : cycle_(config), address_(modbus_address), lost_after_(lost_after) {}

uint16_t PlantProgram::first_request(uint8_t* out, uint16_t capacity) {
  reading_ = true;
  const PcRegisters& regs = pc_registers();
  return modbus::build_read_request(out, capacity, address_, modbus::fc::kReadInputRegisters,
                                    regs.station_first, regs.station_count);
}

void PlantProgram::fail() {
  ++failures_;
  if (failures_ == lost_after_) ++link_losses_;
  if (link_lost()) cycle_.link_lost();
}

uint16_t PlantProgram::on_response(const modbus::Response* r, uint8_t* out, uint16_t capacity) {
  if (!reading_) {  // the write's answer ends the cycle
    if (r == nullptr) fail();
    return 0;
  }
  reading_ = false;
  if (r == nullptr) {
    fail();
    const plant::Actuators& a = cycle_.controller().outputs().plant;
    if (link_lost() && (a.motor_on || a.valve_open)) ++unsafe_while_lost_;
    cycle_.step_offline();  // without inputs the PC cannot decide: last (or safe) outputs
    return 0;
  }
  failures_ = 0;
  const PcRegisters& regs = pc_registers();
  // A field's registers within the block read from station_first on.
  const bool run = cycle_.step(plant::decode_panel([&](Field f) {
    const gateway::MapItem& item = regs.input[static_cast<int>(f)];
    if (!item.mapped() || item.first < regs.station_first ||
        item.first + item.width > regs.station_first + regs.station_count) {
      return uint32_t{0};
    }
    uint32_t value = 0;
    for (uint16_t k = 0; k < item.width; ++k) {
      value = (value << 16) | r->reg(static_cast<uint16_t>(item.first - regs.station_first + k));
    }
    return value;
  }));
  return modbus::build_write_single_register(out, capacity, address_, regs.run_command, run ? 1 : 0);
}

uint16_t LabProgram::first_request(uint8_t* out, uint16_t capacity) {
  reading_ = true;
  const PcRegisters& regs = pc_registers();
  if (remote_) {
    return modbus::build_read_request(out, capacity, address_, modbus::fc::kReadInputRegisters,
                                      regs.remote_buttons, 1);
  }
  return modbus::build_read_request(out, capacity, address_, modbus::fc::kReadDiscreteInputs, regs.start, 1);
}

uint16_t LabProgram::on_response(const modbus::Response* r, uint8_t* out, uint16_t capacity) {
  if (!reading_ || r == nullptr) return 0;
  reading_ = false;
  const bool pressed = remote_ ? (r->reg(0) & 0x01) != 0 : r->bit(0);
  const bool led = lab_.step(pressed);
  return modbus::build_write_single_coil(out, capacity, address_, pc_registers().lab_led, led);
}

}  // namespace sim
}  // namespace mb2co
