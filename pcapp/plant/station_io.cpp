#include "station_io.h"

namespace mb2co {
namespace pcapp {

namespace {
int slot(RegTable t) {
  return t == RegTable::kHolding ? 0 : 1;
}
}  // namespace

void RegisterImage::resize(const TransactionPlan& plan) {
  regs[0].assign(plan.read_registers[0], 0);
  regs[1].assign(plan.read_registers[1], 0);
}

uint16_t* RegisterImage::block(const Block& b) {
  return regs[slot(b.table)].data() + b.start;
}

uint32_t RegisterImage::get(const RegisterLayout& layout, Field field) const {
  const Location& l = layout[field];
  if (l.table == RegTable::kNone) return 0;
  const std::vector<uint16_t>& r = regs[slot(l.table)];
  if (static_cast<size_t>(l.address) + l.width > r.size()) return 0;
  return l.width == 2 ? (uint32_t{r[l.address]} << 16) | r[l.address + 1u] : r[l.address];
}

void RegisterImage::put(const RegisterLayout& layout, Field field, uint16_t value) {
  const Location& l = layout[field];
  if (l.table == RegTable::kNone) return;
  std::vector<uint16_t>& r = regs[slot(l.table)];
  if (l.address < r.size()) r[l.address] = value;
}

Panel decode_panel(const RegisterLayout& layout, const RegisterImage& image) {
  return plant::decode_panel([&](Field f) { return image.get(layout, f); });
}

}  // namespace pcapp
}  // namespace mb2co
