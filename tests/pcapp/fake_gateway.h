// The register image a gateway would answer, for driving the cycle modes
// without a link: set fields by name, read what the mode wrote.
#pragma once
#include "register_layout.h"
#include "station_io.h"
#include "transaction_plan.h"

namespace mb2co {
namespace pcapp {

struct FakeGateway {
  RegisterLayout layout = default_layout();
  RegisterImage in;
  RegisterImage out;

  FakeGateway() {
    TransactionPlan p;
    p.read_registers[0] = static_cast<uint16_t>(layout.mapped[0].size());
    p.read_registers[1] = static_cast<uint16_t>(layout.mapped[1].size());
    in.resize(p);
    out.resize(p);
  }
  void set(Field f, uint32_t v) {
    const Location& l = layout[f];
    std::vector<uint16_t>& r = in.regs[l.table == RegTable::kHolding ? 0 : 1];
    if (l.width == 2) {
      r[l.address] = static_cast<uint16_t>(v >> 16);
      r[l.address + 1u] = static_cast<uint16_t>(v);
    } else {
      r[l.address] = static_cast<uint16_t>(v);
    }
  }
  uint32_t written(Field f) const { return out.get(layout, f); }
};

}  // namespace pcapp
}  // namespace mb2co
