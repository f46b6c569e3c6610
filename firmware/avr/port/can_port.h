// The MCP2515 under a device on the Uno (gateway::Gateway, ionode::IoNode,
// serialnet::Bridge), the CAN half of the platform contract
// (shared/platform/device_port.h): sends frames, follows the bit rate and
// the acceptance filters the core sets, services the chip (when INT is low,
// and every kServicePeriodUs anyway: bus-off recovery raises no interrupt),
// and hands every received frame and the controller's events to the device
// (CanInput), which routes them. It knows no OD index and no service.
// Portable: the INT level comes in as an argument (port/can_int.h reads it
// on the Uno), so the host builds and tests this code against the chip model.
//
// Filters: set_filters hands in the device's acceptance ranges; the port
// plans filters for the ids they admit (mcp2515::admitted_ids). A plan takes
// tens of ms (filter_plan.h), so it is computed a step (~1 ms) per poll()
// while the filters stay open (accept all: no frame the device needs is
// missed, it ignores the rest), then programmed; new ranges meanwhile start
// it again. A range of more than one id, or more ids than the planner
// takes, keep the filters open. A device with a range of more than one id
// (a network gateway: every node's SDO responses and heartbeats) gets
// CanPort<false> through CanPortFor: filters always open, no planner in the
// image.
#pragma once
#include <stdint.h>

#include "mcp2515.h"
#include "platform/device_port.h"

namespace mb2co {
namespace avr {

/// What a port planning filters keeps (CanPort<true>).
struct PlannedFilters {
  /// The ids the ranges of set_filters admit, sorted: what the filters admit
  /// or are being planned for (the planner reads them: they change only
  /// when it is restarted).
  uint16_t ids[mcp2515::kMaxSubscribedIds];
  uint8_t id_count;                ///< 0: none given yet, or more than the planner takes (open)
  mcp2515::FilterPlanner planner;  ///< busy: planning for ids
};
struct NoFilters {};
template <bool kPlansFilters>
struct FilterState {
  typedef NoFilters Type;
};
template <>
struct FilterState<true> {
  typedef PlannedFilters Type;
};

/// The port's state, all zero at the start: CanPort value-initialises it as
/// one block (one zero-fill instead of a store per member).
template <bool kPlansFilters>
struct CanPortState {
  uint32_t last_service_us_;
  uint16_t kbit_;
  bool ready_;
  bool open_;   ///< the chip accepts every frame (begin(), accept_all())
  bool stale_;  ///< the chip's filters are unknown: open and plan again next period
  typename FilterState<kPlansFilters>::Type filters_;
};

/// kPlansFilters: the port plans the chip's filters for the device's ranges
/// (its CanControl has set_filters); false: they stay open and the image
/// carries no planner.
template <bool kPlansFilters>
class CanPort : private CanPortState<kPlansFilters> {
  typedef CanPortState<kPlansFilters> State;
  using State::filters_;
  using State::kbit_;
  using State::last_service_us_;
  using State::open_;
  using State::ready_;
  using State::stale_;

 public:
  static const uint32_t kServicePeriodUs = 10000;
  /// How often the chip is restarted while it does not answer.
  static const uint32_t kRetryUs = 1000000;

  explicit CanPort(mcp2515::Driver& driver) : State(), driver_(driver) {}

  /// The contract's functions; ctx is the CanPort (platform/device_port.h).
  static bool send_to(void* ctx, const CanFrame& frame) { return static_cast<CanPort*>(ctx)->send(frame); }
  static const CanControl kControl;  ///< MB2CO_FLASH

  /// Starts the chip at `kbit` (125, 250, 500 or 1000; others: 500 kbit/s),
  /// accepting every frame until the filters are planned. False when it does
  /// not answer: poll() retries every kRetryUs.
  bool begin(uint16_t kbit, uint32_t now_us);
  /// Restarts the chip when `kbit` differs from the rate in use (frames still
  /// waiting in the chip are lost); the filters are planned again.
  void set_bitrate(uint16_t kbit);
  /// Admit what ranges[0..count) admit: open now, planned filters once the
  /// plan is ready; open for good where mcp2515::admitted_ids finds no plan
  /// (a range of several ids, more ids than the planner takes).
  void set_filters(const CanIdRange* ranges, uint8_t count);
  /// Queues `frame` (false: chip not ready, or its 3 buffers are busy).
  bool send(const CanFrame& frame) { return ready_ && driver_.send(frame); }
  /// Call every loop pass, from the loop (not an ISR), with the INT pin's
  /// level: hands every received frame to `device` (and the controller's
  /// events, when it takes them). A pass plans at most one step
  /// (FilterPlanner).
  void poll(CanInput device, bool int_low, uint32_t now_us);

  bool ready() const { return ready_; }

 private:
  static void set_bitrate_of(void* ctx, uint16_t kbit) { static_cast<CanPort*>(ctx)->set_bitrate(kbit); }
  static void set_filters_of(void* ctx, const CanIdRange* ranges, uint8_t count) {
    static_cast<CanPort*>(ctx)->set_filters(ranges, count);
  }
  bool start(uint16_t kbit);
  void service(CanInput device, uint32_t now_us);
  void restart_filters();
  void step_plan();
  void program_plan();

  mcp2515::Driver& driver_;
};

template <>
const CanControl CanPort<true>::kControl;
template <>
const CanControl CanPort<false>::kControl;
// Open filters: nothing to plan, the chip stays as begin() left it (its
// kControl has no set_filters).
template <>
inline void CanPort<false>::restart_filters() {}
template <>
inline void CanPort<false>::step_plan() {}
template <>
inline void CanPort<false>::set_filters(const CanIdRange*, uint8_t) {}
template <>
inline void CanPort<false>::program_plan() {}
extern template class CanPort<true>;
extern template class CanPort<false>;

/// The port for a device whose widest acceptance range admits
/// `kWidestRange` ids (Gateway::kWidestRange, IoNode::kWidestRange): it
/// plans filters when every range is a single id (what the planner takes),
/// else keeps them open and leaves the planner out.
template <uint16_t kWidestRange>
using CanPortFor = CanPort<kWidestRange == 1>;

}  // namespace avr
}  // namespace mb2co
