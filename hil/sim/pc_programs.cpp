#include "sim/pc_programs.h"

#include "gateway/line_app.h"
#include "modbus/protocol.h"

namespace mb2co {
namespace sim {
namespace {

plant::NeighbourState neighbour(uint16_t status, uint16_t run) {
  switch (status) {
    case gateway::kNeighbourAlive:
      return run != 0 ? plant::NeighbourState::running : plant::NeighbourState::stopped;
    case gateway::kNeighbourNone:
      return plant::NeighbourState::absent;
    default:
      return plant::NeighbourState::unknown;
  }
}

}  // namespace

PlantProgram::PlantProgram(const plant::PlantConfig& config, uint8_t modbus_address, uint32_t lost_after)
    : plant_(config),
      controller_(plant::controller_config_for(config)),
      address_(modbus_address),
      lost_after_(lost_after) {}

uint16_t PlantProgram::first_request(uint8_t* out, uint16_t capacity) {
  reading_ = true;
  return modbus::build_read_request(out, capacity, address_, modbus::fc::kReadInputRegisters,
                                    regs::kIrButtons, regs::kIrStationBlock);
}

void PlantProgram::fail() {
  ++failures_;
  if (failures_ == lost_after_) ++link_losses_;
  if (link_lost()) controller_.force_safe();
}

uint16_t PlantProgram::on_response(const modbus::Response* r, uint8_t* out, uint16_t capacity) {
  if (!reading_) {  // the write's answer ends the cycle
    if (r == nullptr) fail();
    return 0;
  }
  reading_ = false;
  if (r == nullptr) {
    fail();
    const plant::Actuators& a = controller_.outputs().plant;
    if (link_lost() && (a.motor_on || a.valve_open)) ++unsafe_while_lost_;
    plant_.step(a);  // without inputs the PC cannot decide: last (or safe) outputs
    return 0;
  }
  failures_ = 0;
  plant::ControllerInputs in;
  // Registers of the block read from kIrButtons on.
  auto reg = [r](uint16_t address) { return r->reg(static_cast<uint16_t>(address - regs::kIrButtons)); };
  const uint16_t buttons = reg(regs::kIrButtons);
  in.start_pressed = (buttons & gateway::kStart) != 0;
  in.stop_pressed = (buttons & gateway::kStop) != 0;
  in.stop2_pressed = (buttons & gateway::kStop2) != 0;
  in.local_stop2_events = reg(regs::kIrStop2Count);
  in.prev_stop2_events = reg(regs::kIrPrevStop2);
  in.prev_stop2_known = (reg(regs::kIrPrevStatus) & gateway::kNeighbourNotHeard) == 0;
  in.prev_run = neighbour(reg(regs::kIrPrevStatus), reg(regs::kIrPrevRun));
  in.next_run = neighbour(reg(regs::kIrNextStatus), reg(regs::kIrNextRun));
  in.plant = plant_.sensors();
  const plant::ControllerOutputs& o = controller_.step(in);
  plant_.step(o.plant);
  return modbus::build_write_single_register(out, capacity, address_, regs::kHrRunCommand,
                                             o.run == plant::RunState::running ? 1 : 0);
}

uint16_t LabProgram::first_request(uint8_t* out, uint16_t capacity) {
  reading_ = true;
  if (remote_) {
    return modbus::build_read_request(out, capacity, address_, modbus::fc::kReadInputRegisters,
                                      regs::kIrRemoteButtons, 1);
  }
  return modbus::build_read_request(out, capacity, address_, modbus::fc::kReadDiscreteInputs, regs::kDiStart,
                                    1);
}

uint16_t LabProgram::on_response(const modbus::Response* r, uint8_t* out, uint16_t capacity) {
  if (!reading_ || r == nullptr) return 0;
  reading_ = false;
  const bool pressed = remote_ ? (r->reg(0) & 0x01) != 0 : r->bit(0);
  const bool led = lab_.step(pressed);
  return modbus::build_write_single_coil(out, capacity, address_, regs::kCoilLabLed, led);
}

}  // namespace sim
}  // namespace mb2co
