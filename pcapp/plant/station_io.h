// Registers <-> controller: the register image one cycle read, decoded into
// the operator panel's state, and turned into plant::ControllerInputs.
#pragma once
#include <stdint.h>

#include <vector>

#include "plant/controller.h"
#include "register_layout.h"
#include "transaction_plan.h"

namespace mb2co {
namespace pcapp {

/// The registers of the last read, indexed by address, per table. Sized from
/// a plan; fields outside the image read as 0.
struct RegisterImage {
  std::vector<uint16_t> regs[2];  ///< [0] holding, [1] input

  void resize(const TransactionPlan& plan);
  uint16_t* block(const Block& b);
  /// 8/16-bit fields: the register; 32-bit: high word first.
  uint32_t get(const RegisterLayout& layout, Field field) const;
  void put(const RegisterLayout& layout, Field field, uint16_t value);
};

/// What the gateway reported in one read (0 for fields the map lacks).
struct Panel {
  uint8_t buttons = 0;  ///< gateway::Button bits, debounced
  uint8_t run_state = 0;
  uint8_t stop_cause = 0;  ///< gateway::StopCause
  uint8_t leds = 0;        ///< gateway::Led bits
  uint8_t prev_run = 0, prev_status = 0, next_run = 0, next_status = 0;
  uint8_t error_register = 0, nmt_state = 0;
  uint16_t stop2_count = 0, prev_stop2 = 0, start_count = 0, stop_count = 0;
};

Panel decode_panel(const RegisterLayout& layout, const RegisterImage& image);

/// A neighbour as the controller sees it: status 1 (alive) gives its RUN
/// state, 0 unknown (heartbeat lost), 2 none (end of the chain) absent; with
/// the flag kNeighbourNotHeard (no TPDO1 yet) unknown.
plant::NeighbourState neighbour_state(uint8_t status, uint8_t run);

/// The controller's inputs; the previous STOP2 counter counts only when
/// heard (prev_status without kNeighbourNotHeard). `run_confirmed`: the RUN command 1 was written
/// before the previous read already, so a firmware RUN state 0 with stop
/// cause "STOP button" is a latched STOP press; it counts as STOP held, and
/// a click shorter than one cycle (never seen as a level) still stops.
plant::ControllerInputs controller_inputs(const Panel& panel, bool run_confirmed,
                                          const plant::Sensors& sensors);

}  // namespace pcapp
}  // namespace mb2co
