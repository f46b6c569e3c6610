// Registers <-> station cycle: the register image one cycle read, decoded
// into the operator panel's state (plant::Panel).
#pragma once
#include <stdint.h>

#include <vector>

#include "plant/station_cycle.h"
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

/// The station cycle's panel, decoding and controller inputs (shared/plant).
using plant::controller_inputs;
using plant::neighbour_state;
using plant::Panel;

/// The panel as `image` holds it (0 for fields the layout lacks).
Panel decode_panel(const RegisterLayout& layout, const RegisterImage& image);

}  // namespace pcapp
}  // namespace mb2co
