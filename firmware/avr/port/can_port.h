// The MCP2515 under a canopen::Node on the Uno, the CAN half of the platform
// contract (shared/platform/device_port.h): sends frames, follows the bit rate and the
// acceptance filters the core sets, services the chip (when INT is low, and
// every kServicePeriodUs anyway: bus-off recovery raises no interrupt),
// hands received frames to the node and reports controller events to it
// (Node::on_controller_state decides the EMCY). It knows no OD index.
//
// Filters: set_filters hands in the ids the node consumes. A plan takes tens
// of ms (filter_plan.h), so it is computed a step (~1 ms) per poll() while
// the filters stay open (accept all: no consumed frame is missed, the node
// ignores the rest), then programmed; new ids meanwhile start it again.
// Remote requests for TPDOs are filtered out (RTR is deprecated, CiA AN 802).
// A network gateway (built with FC 2Bh/0Dh) keeps the filters open: it must
// hear every node's SDO responses and heartbeats (can_port.cpp).
#pragma once
#include <stdint.h>

#include "canopen/node.h"
#include "mcp2515.h"

namespace mb2co {
namespace avr {

static_assert(canopen::kMaxConsumedIds <= mcp2515::kMaxSubscribedIds,
              "every id the node consumes fits the filter planner");

/// The port's state, all zero at the start: CanPort value-initialises it as
/// one block (one zero-fill instead of a store per member).
struct CanPortState {
  /// The ids set_filters gave, sorted: what the filters admit or are being
  /// planned for (planner_ reads them: they change only when it is restarted).
  uint16_t ids_[mcp2515::kMaxSubscribedIds];
  uint8_t id_count_;  ///< 0: none given yet (filters stay open)
  uint16_t kbit_;
  uint32_t last_service_us_;
  bool ready_;
  bool open_;                       ///< the chip accepts every frame (begin(), accept_all())
  bool stale_;                      ///< the chip's filters are unknown: open and plan again next period
  mcp2515::FilterPlanner planner_;  ///< busy: planning for ids_
};

class CanPort : private CanPortState {
 public:
  static const uint32_t kServicePeriodUs = 10000;
  /// How often the chip is restarted while it does not answer.
  static const uint32_t kRetryUs = 1000000;

  explicit CanPort(mcp2515::Driver& driver) : CanPortState(), driver_(driver) {}

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
  /// Admit ids[0..count) (sorted): open now, exact once planned.
  void set_filters(const uint16_t* ids, uint8_t count);
  /// Queues `frame` (false: chip not ready, or its 3 buffers are busy).
  bool send(const CanFrame& frame) { return ready_ && driver_.send(frame); }
  /// Call every loop pass, from the loop (not an ISR). A pass plans at most
  /// one step (FilterPlanner).
  void poll(canopen::Node& node, uint32_t now_us);

  bool ready() const { return ready_; }

 private:
  static void set_bitrate_of(void* ctx, uint16_t kbit) { static_cast<CanPort*>(ctx)->set_bitrate(kbit); }
  static void set_filters_of(void* ctx, const uint16_t* ids, uint8_t count) {
    static_cast<CanPort*>(ctx)->set_filters(ids, count);
  }
  bool start(uint16_t kbit);
  void service(canopen::Node& node, uint32_t now_us);
  void restart_filters();
  void program_plan();

  mcp2515::Driver& driver_;
};

}  // namespace avr
}  // namespace mb2co
