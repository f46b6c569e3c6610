#include "port/can_port.h"

#include <avr/io.h>
#include <string.h>

#include "modbus/net_switch.h"
#include "pins.h"

namespace mb2co {
namespace avr {
namespace {

namespace can = mcp2515;

static_assert(pins::kCanInt == 2, "INT is read from PIND2 below");
// The driver's events are handed to the core unchanged.
static_assert(unsigned{can::kEventRxOverflow} == kControllerRxOverflow &&
                  unsigned{can::kEventStateChanged} == kControllerStateChanged &&
                  unsigned{can::kEventBusOffRecovered} == kControllerBusOffRecovered,
              "mcp2515 events are ControllerEvent bits");

bool int_low() {
  return (PIND & _BV(PIND2)) == 0;
}

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

// A network gateway (FC 2Bh/0Dh, modbus/net_switch.h) hears every node: its
// SDO client's responses come on 580h + any node id and its network view
// wants every heartbeat (701h-77Fh), ids the node's consumed list does not
// hold. Its filters stay open, as mb2co-node then opens its kernel filter:
// the core has no set_filters to call and the planner is not in the image.
constexpr bool kPlansFilters = !MB2CO_GATEWAY_NET;
const CanControl CanPort::kControl MB2CO_FLASH = {&CanPort::set_bitrate_of,
                                                  kPlansFilters ? &CanPort::set_filters_of : nullptr};

bool CanPort::begin(uint16_t kbit, uint32_t now_us) {
  last_service_us_ = now_us;
  return start(kbit);
}

bool CanPort::start(uint16_t kbit) {
  kbit_ = kbit;
  ready_ = driver_.begin(bitrate_of(kbit), can::Mode::kNormal);
  open_ = ready_;  // the chip accepts everything after begin()
  restart_filters();
  return ready_;
}

void CanPort::set_bitrate(uint16_t kbit) {
  if (kbit != kbit_) start(kbit);
}

void CanPort::set_filters(const uint16_t* ids, uint8_t count) {
  const uint16_t bytes = static_cast<uint16_t>(count * sizeof ids[0]);
  if (count == id_count_ && memcmp(ids, ids_, bytes) == 0) return;  // the plan in force
  id_count_ = count;
  memcpy(ids_, ids, bytes);
  restart_filters();
}

void CanPort::poll(canopen::Node& node, uint32_t now_us) {
  const bool period = since(now_us, last_service_us_, ready_ ? kServicePeriodUs : kRetryUs);
  if (!ready_) {
    if (period) begin(kbit_, now_us);
    return;
  }
  if (period) {
    last_service_us_ = now_us;
    if (stale_) restart_filters();
    service(node, now_us);
  } else if (int_low()) {
    service(node, now_us);
  }
  CanFrame frame;
  while (driver_.receive(frame)) node.receive(frame, now_us);
  if (kPlansFilters && planner_.busy() && planner_.step()) program_plan();
}

void CanPort::service(canopen::Node& node, uint32_t now_us) {
  const uint8_t events = driver_.service();
  if (events != 0)
    node.on_controller_state(events, driver_.error_state() >= can::ErrorState::kPassive, now_us);
}

void CanPort::restart_filters() {
  planner_.stop();
  stale_ = false;
  if (!kPlansFilters || !ready_ || id_count_ == 0) return;  // begin() opens and plans
  if (!open_) open_ = driver_.accept_all();
  if (open_) {
    planner_.start(ids_, id_count_);
  } else {
    stale_ = true;  // try again next period
  }
}

void CanPort::program_plan() {
  can::FilterPlan plan;
  planner_.plan(plan);
  planner_.stop();
  // On failure the chip's filters are unknown: the next period opens them
  // and plans again.
  open_ = false;
  stale_ = !driver_.set_filters(plan);
}

}  // namespace avr
}  // namespace mb2co
