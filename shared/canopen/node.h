// A CANopen device: the Object Dictionary and every service of the node,
// driven by frames handed in (receive) and time handed in (process). Frames
// leave through the CanSink. No clock reads, no heap: the caller owns the Node
// (statically on the AVR) and calls both functions from one context (not an
// ISR: the port queues frames from its interrupt and hands them in here).
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/emcy_producer.h"
#include "canopen/error_control.h"
#include "canopen/heartbeat_consumer.h"
#include "canopen/nmt_slave.h"
#include "canopen/od.h"
#include "canopen/param_storage.h"
#include "canopen/rpdo.h"
#include "canopen/sdo_server.h"
#include "canopen/sync.h"
#include "canopen/tpdo.h"

namespace mb2co {
namespace canopen {

/// Told after a reset (node or communication) restored defaults and saved
/// parameters, before the services start from the OD and before the boot-up
/// message: the application re-applies what it owns (e.g. 1000h).
typedef void (*ResetCallback)(void* ctx, NmtReset kind);

/// The state of a Node that starts at zero: one block, value-initialised by
/// the Node's constructor (a zero-fill, then the services' few non-zero
/// defaults) instead of a store per member.
struct NodeState {
  const ParamStorage* storage_;
  OdWriteHook app_hook_;
  void* app_ctx_;
  ResetCallback reset_cb_;
  void* reset_ctx_;
  NmtSlave nmt_;
  ErrorControl error_control_;
  HeartbeatConsumer hb_consumer_;
  EmcyProducer emcy_;
  Sync sync_;
  Tpdos tpdos_;
  Rpdos rpdos_;
  SdoServer sdo_;
  /// Rows of 1016h, 1017h, 100Ch, 100Dh (sub 0), in this order.
  enum : uint8_t { k1016, k1017, k100C, k100D, kRows };
  uint16_t row_[kRows];
  uint16_t row_1010_;  ///< 1010h sub 1
  uint8_t node_id_;
  uint8_t next_node_id_;
  NmtReset pending_reset_;
  bool params_loaded_;
  bool hb_lost_;
  bool life_lost_;
};

class Node : private NodeState {
 public:
  Node(ObjectDictionary& od, const CanSink& sink);

  /// Optional; without storage 1010h reads 0 and "save" is refused.
  void set_storage(const ParamStorage* storage) { storage_ = storage; }
  /// Writes to entries with kHookApp go to the application.
  void set_app_hook(OdWriteHook hook, void* ctx) {
    app_hook_ = hook;
    app_ctx_ = ctx;
  }
  void set_reset_callback(ResetCallback cb, void* ctx) {
    reset_cb_ = cb;
    reset_ctx_ = ctx;
  }
  /// Node id used from the next reset communication on (1..127).
  void set_node_id_for_next_reset(uint8_t node_id) { next_node_id_ = node_id; }

  /// A reset as if by NMT command, carried out at the next process() (so that
  /// a response to the request that asked for it can still leave first).
  void request_reset(NmtReset kind) { pending_reset_ = kind; }
  /// An NMT command given by the device itself (a self-starting node enters
  /// operational without a master), with the same effects as on the bus.
  void local_nmt(NmtCommand command, uint32_t now_us);
  /// True when the last reset found a valid saved-parameter image.
  bool params_loaded() const { return params_loaded_; }

  /// Power-on: defaults and saved parameters, boot-up, pre-operational.
  void start(uint8_t node_id, uint32_t now_us);
  void receive(const CanFrame& f, uint32_t now_us);
  void process(uint32_t now_us);

  NmtState nmt_state() const { return nmt_.state(); }
  uint8_t node_id() const { return node_id_; }
  ObjectDictionary& od() { return od_; }
  EmcyProducer& emcy() { return emcy_; }
  HeartbeatConsumer& heartbeat_consumer() { return hb_consumer_; }
  Tpdos& tpdos() { return tpdos_; }
  Rpdos& rpdos() { return rpdos_; }

 private:
  static uint32_t od_hook(void* ctx, uint8_t hook, uint16_t index, uint8_t sub,
                          const uint8_t* data, uint16_t len);
  uint32_t on_hb_consumer_write(uint8_t sub, uint32_t value);
  uint32_t on_store_write(uint16_t index, uint32_t value);
  void reset(NmtReset kind, uint32_t now_us);
  void enter(NmtState state);
  /// Side effects of a state change that already happened.
  void on_transition(NmtState before);
  void on_sync_event(uint8_t counter, uint32_t now_us);
  void update_guard_emcy();

  ObjectDictionary& od_;
  CanSink sink_;
};

}  // namespace canopen
}  // namespace mb2co
