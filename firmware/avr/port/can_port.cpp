#include "port/can_port.h"

#include <avr/io.h>

#include "pins.h"

namespace mb2co {
namespace avr {
namespace {

using canopen::ObjectDictionary;
namespace can = mcp2515;

static_assert(pins::kCanInt == 2, "INT is read from PIND2 below");

bool int_low() { return (PIND & _BV(PIND2)) == 0; }

can::Bitrate bitrate_of(uint16_t kbit) {
  return kbit == 125 ? can::Bitrate::k125k
         : kbit == 250 ? can::Bitrate::k250k
         : kbit == 1000 ? can::Bitrate::k1000k
                        : can::Bitrate::k500k;
}

bool since(uint32_t now_us, uint32_t then_us, uint32_t span_us) { return now_us - then_us >= span_us; }

// Adds `id` to the sorted, duplicate-free ids[0..count); a count beyond the
// capacity means "too many" (the list is then incomplete).
void add_id(uint16_t* ids, uint8_t& count, uint16_t id) {
  if (count > can::kMaxSubscribedIds) return;
  uint8_t at = 0;
  while (at < count && ids[at] < id) ++at;
  if (at < count && ids[at] == id) return;
  if (count == can::kMaxSubscribedIds) {
    ++count;
    return;
  }
  for (uint8_t i = count; i > at; --i) ids[i] = ids[i - 1];
  ids[at] = id;
  ++count;
}

uint32_t value_at(const ObjectDictionary& od, uint16_t index, uint8_t sub, bool& present) {
  const uint16_t row = od.find(index, sub);
  present = row != ObjectDictionary::kNoRow;
  return present ? od.get(row) : 0;
}

}  // namespace

bool CanPort::begin(uint16_t kbit, uint32_t now_us) {
  kbit_ = kbit;
  last_service_us_ = now_us;
  ready_ = driver_.begin(bitrate_of(kbit), can::Mode::kNormal);
  // The chip accepts everything now; the next period plans the filters (not
  // here: begin() may run inside a send, e.g. the boot-up after a reset).
  open_ = ready_;
  exact_ = false;
  id_count_ = 0;
  planner_.stop();
  return ready_;
}

void CanPort::set_bitrate(uint16_t kbit, uint32_t now_us) {
  if (kbit != kbit_) begin(kbit, now_us);
}

void CanPort::poll(uint32_t now_us) {
  const bool period = since(now_us, last_service_us_, ready_ ? kServicePeriodUs : kRetryUs);
  if (!ready_) {
    if (period) begin(kbit_, now_us);
    return;
  }
  if (period) {
    last_service_us_ = now_us;
    update_filters();
    service(now_us);
  } else if (int_low()) {
    service(now_us);
  }
  CanFrame frame;
  while (driver_.receive(frame)) node_.receive(frame, now_us);
  if (planner_.busy() && planner_.step()) program_plan();
}

void CanPort::service(uint32_t now_us) {
  on_events(driver_.service(), now_us);
  canopen::EmcyProducer& emcy = node_.emcy();
  if (emcy.active(canopen::kEmcyCanOverrun) && since(now_us, overflow_us_, kEventHoldUs)) {
    emcy.clear(canopen::kEmcyCanOverrun);
  }
  if (emcy.active(canopen::kEmcyBusOffRecovered) && since(now_us, recovered_us_, kEventHoldUs)) {
    emcy.clear(canopen::kEmcyBusOffRecovered);
  }
}

void CanPort::on_events(uint8_t events, uint32_t now_us) {
  canopen::EmcyProducer& emcy = node_.emcy();
  if (events & can::kEventRxOverflow) {
    overflow_us_ = now_us;
    emcy.raise(canopen::kEmcyCanOverrun, canopen::kErrCommunication);
  }
  if (events & can::kEventBusOffRecovered) {
    recovered_us_ = now_us;
    emcy.raise(canopen::kEmcyBusOffRecovered, canopen::kErrCommunication);
  }
  if (events & can::kEventStateChanged) {
    if (driver_.error_state() >= can::ErrorState::kPassive) {
      emcy.raise(canopen::kEmcyCanPassive, canopen::kErrCommunication);
    } else {
      emcy.clear(canopen::kEmcyCanPassive);
    }
  }
}

uint8_t CanPort::collect_ids(uint16_t* ids) const {
  const ObjectDictionary& od = node_.od();
  const uint8_t id = node_.node_id();
  uint8_t count = 0;
  bool present = false;
  add_id(ids, count, 0x000);  // NMT
  const uint32_t sync = value_at(od, 0x1005, 0, present);
  if (present) add_id(ids, count, static_cast<uint16_t>(sync & 0x7FFu));
  add_id(ids, count, static_cast<uint16_t>(0x600u + id));  // SDO request
  add_id(ids, count, static_cast<uint16_t>(0x700u + id));  // node guarding (RTR)
  for (uint8_t n = 0; n < 4; ++n) {
    const uint32_t cob = value_at(od, static_cast<uint16_t>(0x1400u + n), 1, present);
    // Valid (bit 31 clear) and a standard id (bit 29 clear).
    if (present && (cob & 0xA0000000u) == 0) add_id(ids, count, static_cast<uint16_t>(cob & 0x7FFu));
  }
  for (uint8_t sub = 1; sub <= canopen::kHbConsumers; ++sub) {
    const uint32_t entry = value_at(od, 0x1016, sub, present);
    const uint8_t remote = static_cast<uint8_t>(entry >> 16);
    // Node id 1..127 and a consumer time: a heartbeat to watch.
    if (present && remote >= 1 && remote <= 127 && (entry & 0xFFFFu) != 0) {
      add_id(ids, count, static_cast<uint16_t>(0x700u + remote));
    }
  }
  return count;
}

void CanPort::update_filters() {
  uint16_t ids[can::kMaxSubscribedIds];
  const uint8_t count = collect_ids(ids);
  if (count == id_count_) {
    uint8_t i = 0;
    while (i < count && i < can::kMaxSubscribedIds && ids[i] == ids_[i]) ++i;
    if (i == count || i == can::kMaxSubscribedIds) return;  // unchanged
  }
  // Changed: open the filters at once, plan in steps (poll()).
  planner_.stop();
  exact_ = false;
  if (!open_) {
    open_ = driver_.accept_all();
    if (!open_) {
      id_count_ = 0;  // try again next period
      return;
    }
  }
  id_count_ = count;
  for (uint8_t i = 0; i < count && i < can::kMaxSubscribedIds; ++i) ids_[i] = ids[i];
  if (count <= can::kMaxSubscribedIds) planner_.start(ids_, count);
}

void CanPort::program_plan() {
  can::FilterPlan plan;
  planner_.plan(plan);
  planner_.stop();
  // On failure the chip's filters are unknown: the next period opens them
  // and plans again.
  open_ = false;
  if (driver_.set_filters(plan)) {
    exact_ = plan.exact;
  } else {
    id_count_ = 0;
  }
}

}  // namespace avr
}  // namespace mb2co
