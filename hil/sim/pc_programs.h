// The control processes a simulated PC runs (shared/plant, the same code as
// the Qt app): the bottling station (plant + controller over the gateway's
// register map, docs/register-map.md) and the latency lab's button-to-LED
// process of seed 000 §11.
#pragma once
#include <stdint.h>

#include "gateway/register_map.h"
#include "plant/latency_lab.h"
#include "plant/station_cycle.h"
#include "sim/pc_station.h"

namespace mb2co {
namespace sim {

/// Where the PC programs' registers are in the gateway's default map,
/// located once by the register map (gateway/register_map.h).
struct PcRegisters {
  /// The input registers the plant program reads in one request: every
  /// field of plant::kStationReads (buttons .. next status).
  uint16_t station_first;
  uint16_t station_count;
  /// Each field's input registers (width 0: not an input register).
  gateway::MapItem input[plant::kFieldCount];
  uint16_t run_command;     ///< holding register
  uint16_t remote_buttons;  ///< input register: the watched station's buttons
  uint16_t start;           ///< discrete input: own START button
  uint16_t lab_led;         ///< coil: bit 0 of the lab LED output
};
const PcRegisters& pc_registers();

/// Per cycle: FC 04 reads the station block (IR 0..10), the station cycle
/// (shared/plant) steps the controller and the plant one step_ms, FC 06
/// writes the RUN command. After `lost_after` failed
/// transactions in a row (1: at once, as the Qt app does) the link counts as
/// lost: Controller::force_safe(), and the plant gets safe actuators.
class PlantProgram : public PcProgram {
 public:
  PlantProgram(const plant::PlantConfig& config, uint8_t modbus_address, uint32_t lost_after = 1);
  uint16_t first_request(uint8_t* out, uint16_t capacity) override;
  uint16_t on_response(const modbus::Response* r, uint8_t* out, uint16_t capacity) override;

  const plant::Plant& plant() const { return cycle_.plant(); }
  const plant::Controller& controller() const { return cycle_.controller(); }
  bool link_lost() const { return failures_ >= lost_after_; }
  /// Cycles in which the link was lost and the plant still got unsafe
  /// actuators (must stay 0).
  uint64_t unsafe_while_lost() const { return unsafe_while_lost_; }
  uint64_t link_losses() const { return link_losses_; }

 private:
  void fail();

  plant::StationCycle cycle_;
  uint8_t address_;
  uint32_t lost_after_;
  uint32_t failures_ = 0;
  bool reading_ = true;
  uint64_t unsafe_while_lost_ = 0;
  uint64_t link_losses_ = 0;
};

/// Seed 000 §11: read a button, write its state to the lab LED (coil 1 of
/// the PC's own Arduino). `remote`: the button is the watched station's,
/// read as an input register (FC 04) after it crossed CANopen; otherwise
/// the own START button, a discrete input (FC 02).
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
