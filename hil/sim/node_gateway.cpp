// NodeStation's gateway: the firmware's gateway core built on the station's
// ports (CAN controller, serial output, EEPROM, filters), the bench
// commissioning, and the OD state the line watches. The pass scheduler is
// node_station.cpp.
#include <algorithm>
#include <stdexcept>
#include <vector>

#include "canopen/pdo_map.h"
#include "filter_plan.h"
#include "plant/station_fields.h"
#include "sim/node_station.h"

namespace mb2co {
namespace sim {

namespace {
// The controller's bit rate is the bus's (can_bus.h): filters only.
const CanControl kCanControl = {nullptr, &NodeStation::set_filters};
}  // namespace

void NodeStation::make_gateway() {
  gateway::GatewayPorts ports{CanSink{&NodeStation::can_send, this},
                              modbus::ByteSink{&NodeStation::serial_send, this}, &eeprom_.storage(), baud_,
                              &kCanControl};
  gw_.reset(new gateway::Gateway(ports));
  if (!timing_.isr_stamps) gw_->modbus_slave().set_check_t15(false);
  canopen::ObjectDictionary& od = gw_->od();
  // The station's entries, by the names every PC program uses (NodeState's
  // order), read after every pass: resolved to their value bytes once,
  // here (the gateway, and so its value block, lives until power off).
  using plant::Field;
  const Field watched[kWatched] = {Field::kNmtState,   Field::kRunState,   Field::kStop2Count,
                                   Field::kPrevStatus, Field::kNextStatus, Field::kPrevRun,
                                   Field::kNextRun};
  const canopen::ObjectDictionary& values = od;
  for (size_t k = 0; k < kWatched; ++k) {
    const uint16_t row = od.find(plant::field_spec(watched[k]).key());
    watched_[k] = values.ram(row);
    watched_size_[k] = static_cast<uint8_t>(values.size_of(row));
    if (watched_[k] == nullptr || watched_size_[k] == 0 || watched_size_[k] > 2) {
      throw std::logic_error("watched OD entry is not a RAM value of 1 or 2 bytes");
    }
  }
}

uint32_t NodeStation::watched(size_t k) const {
  const uint8_t* p = watched_[k];
  return watched_size_[k] == 1 ? p[0] : static_cast<uint32_t>(p[0] | p[1] << 8);
}

void NodeStation::commission(const std::function<void(canopen::ObjectDictionary&)>& configure) {
  bench_ = true;
  make_gateway();
  gw_->start(0, static_cast<uint8_t>(index_ + 1));
  if (configure) configure(gw_->od());
  uint8_t save[4];
  canopen::put_le32(save, canopen::kSaveSignature);
  gw_->od().write(0x1010, 1, save, 4);
  // The save runs over passes, an EEPROM byte each 3.3 ms (eeprom.h): the
  // bench's own clock, before the line's time starts, a call each 100 us.
  // Calls before the core's next deadline and before the EEPROM gets ready
  // (its one input here) change nothing (Gateway::next_deadline): they are
  // left out, the others made at the same 100 us steps as before.
  const uint32_t kStepUs = 100;
  for (uint32_t us = 0; gw_->node().saving();) {
    eeprom_.set_now(us * kNsPerUs);
    gw_->process(us, 0);
    uint32_t at_us = 0;
    const uint32_t ready_us = static_cast<uint32_t>((eeprom_.ready_at() + kNsPerUs - 1) / kNsPerUs);
    uint32_t wake_us = gw_->next_deadline(us, &at_us) ? std::min(at_us, ready_us) : ready_us;
    wake_us = std::max(wake_us, us + kStepUs);
    us = (wake_us + kStepUs - 1) / kStepUs * kStepUs;
  }
  eeprom_.settle();
  gw_.reset();
  bench_ = false;
  tx_pending_.clear();
  serial_pending_.clear();
}

void NodeStation::set_filters(void* ctx, const CanIdRange* ranges, uint8_t count) {
  NodeStation& n = *static_cast<NodeStation*>(ctx);
  if (!n.timing_.can_filters || n.bench_) return;
  // The station the line runs is the Uno's station image: no network
  // service (580h-5FFh, 700h-77Fh) and no TPDO answering remote requests
  // (every remote frame), the host build's ranges wider than one id. Its
  // filters are planned for the node's own ids only, as the Uno plans them.
  std::vector<CanIdRange> station;
  for (const CanIdRange* r = ranges; r < ranges + count; ++r) {
    if (ids_in(*r) == 1) station.push_back(*r);
  }
  // The whole plan at once: the firmware's planner reaches the same plan in
  // steps (mcp2515.FilterPlanner tests), with the filters open meanwhile.
  uint16_t ids[mcp2515::kMaxSubscribedIds];
  const uint8_t n_ids = mcp2515::admitted_ids(station.data(), static_cast<uint8_t>(station.size()), ids);
  mcp2515::FilterPlan plan;
  n.can_.set_acceptance(n_ids != 0 && mcp2515::plan_filters(ids, n_ids, plan) ? &plan : nullptr);
}

NodeState NodeStation::read_state() const {
  NodeState s;
  s.nmt = static_cast<uint8_t>(watched(0));
  s.run = static_cast<uint8_t>(watched(1));
  s.stop2_count = static_cast<uint16_t>(watched(2));
  s.prev_status = static_cast<uint8_t>(watched(3));
  s.next_status = static_cast<uint8_t>(watched(4));
  s.prev_run = static_cast<uint8_t>(watched(5));
  s.next_run = static_cast<uint8_t>(watched(6));
  return s;
}

bool NodeStation::can_send(void* ctx, const CanFrame& f) {
  NodeStation& n = *static_cast<NodeStation*>(ctx);
  if (n.bench_) return true;
  // A full controller refuses: the core keeps the frame due (retries it).
  if (n.can_.free_tx() <= static_cast<int>(n.tx_pending_.size())) return false;
  n.tx_pending_.push_back(f);
  return true;
}

bool NodeStation::serial_send(void* ctx, const uint8_t* data, uint16_t len) {
  NodeStation& n = *static_cast<NodeStation*>(ctx);
  if (!n.bench_) n.serial_pending_.insert(n.serial_pending_.end(), data, data + len);
  return true;
}

}  // namespace sim
}  // namespace mb2co
