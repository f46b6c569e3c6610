#include "station_io.h"

#include "gateway/line_app.h"

namespace mb2co {
namespace pcapp {

namespace {
int slot(RegTable t) {
  return t == RegTable::holding ? 0 : 1;
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
  if (l.table == RegTable::none) return 0;
  const std::vector<uint16_t>& r = regs[slot(l.table)];
  if (static_cast<size_t>(l.address) + l.width > r.size()) return 0;
  return l.width == 2 ? (uint32_t{r[l.address]} << 16) | r[l.address + 1u] : r[l.address];
}

void RegisterImage::put(const RegisterLayout& layout, Field field, uint16_t value) {
  const Location& l = layout[field];
  if (l.table == RegTable::none) return;
  std::vector<uint16_t>& r = regs[slot(l.table)];
  if (l.address < r.size()) r[l.address] = value;
}

Panel decode_panel(const RegisterLayout& layout, const RegisterImage& image) {
  auto u8 = [&](Field f) { return static_cast<uint8_t>(image.get(layout, f)); };
  auto u16 = [&](Field f) { return static_cast<uint16_t>(image.get(layout, f)); };
  Panel p;
  p.buttons = u8(Field::inputs);
  p.run_state = u8(Field::run_state);
  p.stop_cause = u8(Field::stop_cause);
  p.leds = u8(Field::leds);
  p.prev_run = u8(Field::prev_run);
  p.prev_status = u8(Field::prev_status);
  p.next_run = u8(Field::next_run);
  p.next_status = u8(Field::next_status);
  p.error_register = u8(Field::error_register);
  p.nmt_state = u8(Field::nmt_state);
  p.stop2_count = u16(Field::stop2_count);
  p.prev_stop2 = u16(Field::prev_stop2);
  p.start_count = u16(Field::start_count);
  p.stop_count = u16(Field::stop_count);
  return p;
}

plant::NeighbourState neighbour_state(uint8_t status, uint8_t run) {
  switch (status) {
    case gateway::kNeighbourAlive:
      return run != 0 ? plant::NeighbourState::running : plant::NeighbourState::stopped;
    case gateway::kNeighbourNone:
      return plant::NeighbourState::absent;
    default:
      // Lost, not heard since the gateway's reset (kNeighbourNotHeard), or a
      // status we do not know: never "running".
      return plant::NeighbourState::unknown;
  }
}

plant::ControllerInputs controller_inputs(const Panel& panel, bool run_confirmed,
                                          const plant::Sensors& sensors) {
  plant::ControllerInputs in;
  in.start_pressed = (panel.buttons & gateway::kStart) != 0;
  const bool latched_stop = run_confirmed && panel.run_state == 0 &&
                            panel.stop_cause == plant::reported_cause(plant::StopCause::stop_button);
  in.stop_pressed = (panel.buttons & gateway::kStop) != 0 || latched_stop;
  in.stop2_pressed = (panel.buttons & gateway::kStop2) != 0;
  in.local_stop2_events = panel.stop2_count;
  in.prev_stop2_events = panel.prev_stop2;
  in.prev_stop2_known = (panel.prev_status & gateway::kNeighbourNotHeard) == 0;
  in.prev_run = neighbour_state(panel.prev_status, panel.prev_run);
  in.next_run = neighbour_state(panel.next_status, panel.next_run);
  in.plant = sensors;
  return in;
}

}  // namespace pcapp
}  // namespace mb2co
