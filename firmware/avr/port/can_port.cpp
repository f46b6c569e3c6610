#include "port/can_port.h"

#include <string.h>

namespace mb2co {
namespace avr {
namespace {

namespace can = mcp2515;

// The driver's events are handed to the device unchanged.
static_assert(unsigned{can::kEventRxOverflow} == kControllerRxOverflow &&
                  unsigned{can::kEventStateChanged} == kControllerStateChanged &&
                  unsigned{can::kEventBusOffRecovered} == kControllerBusOffRecovered,
              "mcp2515 events are ControllerEvent bits");

can::Bitrate bitrate_of(uint16_t kbit) {
  return kbit == 125    ? can::Bitrate::k125k
         : kbit == 250  ? can::Bitrate::k250k
         : kbit == 1000 ? can::Bitrate::k1000k
                        : can::Bitrate::k500k;
}

bool since(uint32_t now_us, uint32_t then_us, uint32_t span_us) {
  return now_us - then_us >= span_us;
}

}  // namespace

template <>
const CanControl CanPort<true>::kControl MB2CO_FLASH = {&CanPort::set_bitrate_of, &CanPort::set_filters_of};
// The device's ranges are wider than the planner: nothing to set, the chip
// stays open after begin().
template <>
const CanControl CanPort<false>::kControl MB2CO_FLASH = {&CanPort::set_bitrate_of, nullptr};

template <bool kPlansFilters>
bool CanPort<kPlansFilters>::begin(uint16_t kbit, uint32_t now_us) {
  last_service_us_ = now_us;
  return start(kbit);
}

template <bool kPlansFilters>
bool CanPort<kPlansFilters>::start(uint16_t kbit) {
  kbit_ = kbit;
  ready_ = driver_.begin(bitrate_of(kbit), can::Mode::kNormal);
  open_ = ready_;  // the chip accepts everything after begin()
  restart_filters();
  return ready_;
}

template <bool kPlansFilters>
void CanPort<kPlansFilters>::set_bitrate(uint16_t kbit) {
  if (kbit != kbit_) start(kbit);
}

template <bool kPlansFilters>
void CanPort<kPlansFilters>::set_filters(const CanIdRange* ranges, uint8_t count) {
  uint16_t ids[can::kMaxSubscribedIds];
  const uint8_t n = can::admitted_ids(ranges, count, ids);
  PlannedFilters& f = filters_;
  // Copied over the ids in force in one pass (the planner reads them only
  // in step(), restarted below when they changed).
  bool same = n == f.id_count;
  for (uint8_t i = 0; i < n; ++i) {
    same = same && f.ids[i] == ids[i];
    f.ids[i] = ids[i];
  }
  if (same) return;  // the plan in force
  f.id_count = n;
  restart_filters();
}

template <bool kPlansFilters>
void CanPort<kPlansFilters>::poll(CanInput device, bool int_low, uint32_t now_us) {
  const bool period = since(now_us, last_service_us_, ready_ ? kServicePeriodUs : kRetryUs);
  if (!ready_) {
    if (period) begin(kbit_, now_us);
    return;
  }
  if (period) {
    last_service_us_ = now_us;
    if (stale_) restart_filters();
    service(device, now_us);
  } else if (int_low) {
    service(device, now_us);
  }
  CanFrame frame;
  while (driver_.receive(frame)) device.receive(device.ctx, frame, now_us);
  step_plan();
}

template <bool kPlansFilters>
void CanPort<kPlansFilters>::service(CanInput device, uint32_t now_us) {
  const uint8_t events = driver_.service();
  if (events != 0 && device.controller_state != nullptr) {
    device.controller_state(device.ctx, events, driver_.error_state() >= can::ErrorState::kPassive, now_us);
  }
}

template <bool kPlansFilters>
void CanPort<kPlansFilters>::restart_filters() {
  PlannedFilters& f = filters_;
  f.planner.stop();
  stale_ = false;
  if (!ready_) return;  // begin() opens and plans
  if (!open_) open_ = driver_.accept_all();
  if (!open_) {
    stale_ = true;  // try again next period
  } else if (f.id_count != 0) {
    f.planner.start(f.ids, f.id_count);
  }
}

template <bool kPlansFilters>
void CanPort<kPlansFilters>::step_plan() {
  if (filters_.planner.busy() && filters_.planner.step()) program_plan();
}

template <bool kPlansFilters>
void CanPort<kPlansFilters>::program_plan() {
  can::FilterPlan plan;
  filters_.planner.plan(plan);
  filters_.planner.stop();
  // On failure the chip's filters are unknown: the next period opens them
  // and plans again.
  open_ = false;
  stale_ = !driver_.set_filters(plan);
}

template class CanPort<true>;
template class CanPort<false>;

}  // namespace avr
}  // namespace mb2co
