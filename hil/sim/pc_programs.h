// The control processes a simulated PC runs (shared/plant, the same code as
// the Qt app): the bottling station (plant + controller over the gateway's
// register map, docs/register-map.md) and the latency lab's button-to-LED
// process of seed 000 §11.
#pragma once
#include <stdint.h>

#include "gateway/gateway_od.h"
#include "plant/controller.h"
#include "plant/latency_lab.h"
#include "plant/plant.h"
#include "sim/pc_station.h"

namespace mb2co {
namespace sim {

/// Register map addresses used by the PC programs: the gateway's default
/// map, looked up by the entries' names at compile time.
namespace regs {
namespace e = gateway::od::GatewayEntry;
constexpr uint16_t ir(canopen::OdKey entry) {
  return gateway::default_map_address(0x2401, entry);
}
constexpr uint16_t kIrButtons = ir(e::x6000_1_readInput8Bit1);  ///< START, STOP, STOP2 bits
constexpr uint16_t kIrStop2Count = ir(e::x2100_3_stop2Count);
constexpr uint16_t kIrPrevRun = ir(e::x2110_1_prevRunState);
constexpr uint16_t kIrPrevStop2 = ir(e::x2110_2_prevStop2Count);
constexpr uint16_t kIrPrevStatus = ir(e::x2110_3_prevStatus);
constexpr uint16_t kIrNextRun = ir(e::x2120_1_nextRunState);
constexpr uint16_t kIrNextStatus = ir(e::x2120_3_nextStatus);
/// Input registers the plant program reads in one request: buttons .. next status.
constexpr uint16_t kIrStationBlock = static_cast<uint16_t>(kIrNextStatus + 1u - kIrButtons);
static_assert(kIrButtons < kIrStop2Count && kIrStop2Count < kIrPrevRun && kIrPrevRun < kIrPrevStop2 &&
                  kIrPrevStop2 < kIrPrevStatus && kIrPrevStatus < kIrNextRun && kIrNextRun < kIrNextStatus &&
                  kIrNextStatus != 0xFFFF,
              "the station block is one read of the default input map");
constexpr uint16_t kIrRemoteButtons = ir(e::x2130_1_remoteButtons);  ///< the watched station's buttons
constexpr uint16_t kHrRunCommand = gateway::default_map_address(0x2400, e::x2100_1_runCommand);
constexpr uint16_t kDiStart = gateway::default_map_address(0x2403, e::x2140_1_startPressed);
constexpr uint16_t kCoilLabLed =
    gateway::default_map_address(0x2402, e::x6200_1_writeOutput8Bit1);  ///< bit 0
static_assert(kIrRemoteButtons != 0xFFFF && kHrRunCommand != 0xFFFF && kDiStart != 0xFFFF &&
                  kCoilLabLed != 0xFFFF,
              "entries of the default map");
}  // namespace regs

/// Per cycle: FC 04 reads IR 0..10, the controller steps, the plant steps
/// one step_ms, FC 06 writes the RUN command. After `lost_after` failed
/// transactions in a row (1: at once, as the Qt app does) the link counts as
/// lost: Controller::force_safe(), and the plant gets safe actuators.
class PlantProgram : public PcProgram {
 public:
  PlantProgram(const plant::PlantConfig& config, uint8_t modbus_address, uint32_t lost_after = 1);
  uint16_t first_request(uint8_t* out, uint16_t capacity) override;
  uint16_t on_response(const modbus::Response* r, uint8_t* out, uint16_t capacity) override;

  const plant::Plant& plant() const { return plant_; }
  const plant::Controller& controller() const { return controller_; }
  bool link_lost() const { return failures_ >= lost_after_; }
  /// Cycles in which the link was lost and the plant still got unsafe
  /// actuators (must stay 0).
  uint64_t unsafe_while_lost() const { return unsafe_while_lost_; }
  uint64_t link_losses() const { return link_losses_; }

 private:
  void fail();

  plant::Plant plant_;
  plant::Controller controller_;
  uint8_t address_;
  uint32_t lost_after_;
  uint32_t failures_ = 0;
  bool reading_ = true;
  uint64_t unsafe_while_lost_ = 0;
  uint64_t link_losses_ = 0;
};

/// Seed 000 §11: read a button, write its state to the lab LED (coil 1 of
/// the PC's own Arduino). `remote`: the button is the watched station's,
/// read as input register 18 (FC 04) after it crossed CANopen; otherwise
/// the own START button, discrete input 0 (FC 02).
class LabProgram : public PcProgram {
 public:
  LabProgram(uint8_t modbus_address, bool remote) : address_(modbus_address), remote_(remote) {}
  uint16_t first_request(uint8_t* out, uint16_t capacity) override;
  uint16_t on_response(const modbus::Response* r, uint8_t* out, uint16_t capacity) override;
  const plant::ButtonToLed& lab() const { return lab_; }

 private:
  plant::ButtonToLed lab_;
  uint8_t address_;
  bool remote_;
  bool reading_ = true;
};

}  // namespace sim
}  // namespace mb2co
