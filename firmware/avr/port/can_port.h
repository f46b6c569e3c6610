// The MCP2515 under a canopen::Node on the Uno: services the chip (when INT
// is low, and every kServicePeriodUs anyway: bus-off recovery raises no
// interrupt), hands received frames to the node, reports controller trouble
// by EMCY, keeps the bit rate and the hardware acceptance filters in line
// with the node's Object Dictionary.
//
// Filters admit exactly what the node consumes: NMT 000h, SYNC (1005h),
// SDO 600h+id, node guarding 700h+id, the valid standard RPDO COB-IDs
// (1400h-1403h/1) and 700h+n for every heartbeat consumer 1016h/1-4. The list
// is re-derived every kServicePeriodUs and the filters re-planned when it
// changed (boot, reset communication, new node id, an SDO write to a COB-ID
// or to 1016h). A plan takes tens of ms (filter_plan.h), so it is computed a
// step (~1 ms) per poll() while the filters stay open (accept all: no
// consumed frame is missed, the node ignores the rest), then programmed; a
// change meanwhile starts it again. More than mcp2515::kMaxSubscribedIds
// ids: filters open.
// Remote requests for TPDOs are filtered out (RTR is deprecated, CiA AN 802).
//
// EMCY (error register bit "communication"):
//   8110h CAN overrun: frames were lost; cleared after kEventHoldUs without
//   8120h error passive: while the controller is error passive or bus-off
//   8140h recovered from bus-off: cleared after kEventHoldUs
#pragma once
#include <stdint.h>

#include "canopen/node.h"
#include "mcp2515.h"

namespace mb2co {
namespace avr {

/// The port's state, all zero at the start: CanPort value-initialises it as
/// one block (one zero-fill instead of a store per member: -74 B on the Uno).
struct CanPortState {
  /// The consumed ids, sorted: what the filters admit or are being planned
  /// for (planner_ reads them: they change only when it is restarted).
  uint16_t ids_[mcp2515::kMaxSubscribedIds];
  /// Ids in ids_ (above kMaxSubscribedIds: too many, the first ones kept);
  /// 0: none yet (a list always holds at least NMT 000h).
  uint8_t id_count_;
  uint16_t kbit_;
  uint32_t last_service_us_;
  uint32_t overflow_us_;   ///< last RX overflow (8110h held until + kEventHoldUs)
  uint32_t recovered_us_;  ///< last bus-off recovery (8140h likewise)
  bool ready_;
  bool exact_;
  bool open_;  ///< the chip accepts every frame (begin(), accept_all())
  mcp2515::FilterPlanner planner_;  ///< busy: planning for ids_
};

class CanPort : private CanPortState {
 public:
  static const uint32_t kServicePeriodUs = 10000;
  static const uint32_t kEventHoldUs = 1000000;
  /// How often begin() is retried while the chip does not answer.
  static const uint32_t kRetryUs = 1000000;

  CanPort(mcp2515::Driver& driver, canopen::Node& node) : CanPortState(), driver_(driver), node_(node) {}

  /// Starts the chip at `kbit` (125, 250, 500 or 1000; others: 500 kbit/s),
  /// accepting every frame until the next period plans the filters. False
  /// when it does not answer: poll() retries every kRetryUs.
  bool begin(uint16_t kbit, uint32_t now_us);
  /// Re-initialises the chip when `kbit` differs from the rate in use (frames
  /// still waiting in the chip are lost). Call before every send, so that the
  /// boot-up after a reset communication already leaves at the new rate.
  void set_bitrate(uint16_t kbit, uint32_t now_us);
  /// Queues `frame` (false: chip not ready, or its 3 buffers are busy).
  bool send(const CanFrame& frame) { return ready_ && driver_.send(frame); }
  /// Call every loop pass. A pass plans at most one step (FilterPlanner).
  void poll(uint32_t now_us);

  bool ready() const { return ready_; }
  /// True when the filters admit exactly the subscribed ids.
  bool filters_exact() const { return exact_; }

 private:
  void service(uint32_t now_us);
  void on_events(uint8_t events, uint32_t now_us);
  void update_filters();
  void program_plan();
  uint8_t collect_ids(uint16_t* ids) const;

  mcp2515::Driver& driver_;
  canopen::Node& node_;
};

}  // namespace avr
}  // namespace mb2co
