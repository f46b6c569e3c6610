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
#include "canopen/od_comm.h"
#include "canopen/param_storage.h"
#include "canopen/rpdo.h"
#include "canopen/sdo_server.h"
#include "canopen/sync.h"
#include "canopen/time_stamp.h"
#include "canopen/tpdo.h"
#include "profiles/profile.h"

namespace mb2co {
namespace canopen {

/// Told after a reset (node or communication) restored defaults and saved
/// parameters, before the services start from the OD and before the boot-up
/// message: the application re-applies what it owns (e.g. 1000h).
typedef void (*ResetCallback)(void* ctx, NmtReset kind);

/// Most standard CAN ids a node consumes: NMT, SYNC, SDO request, node
/// guarding, one per RPDO, one per heartbeat consumer, TIME where the
/// profile has it.
const uint8_t kMaxConsumedIds = 4 + kPdoCount + kHbConsumers + (profile::kTime ? 1 : 0);
/// The remote requests the TPDOs answer where the profile has them
/// (profile::kTpdoRtr): every standard remote frame (a TPDO's COB-ID may
/// change with any write of 1800h-1803h; RTR is rare).
constexpr CanIdRange kTpdoRemoteRange = {kCanRangeRemote, kCanRangeRemote};
const uint8_t kRemoteRanges = profile::kTpdoRtr ? 1 : 0;
/// Most ranges of a device's other services besides its node
/// (Node::set_service_ranges: the gateway's network service has 2).
const uint8_t kMaxServiceRanges = 2;
/// Most acceptance ranges a device hands its CAN port (Node::acceptance,
/// CanControl::set_filters).
const uint8_t kMaxAcceptanceRanges = kMaxConsumedIds + kRemoteRanges + kMaxServiceRanges;

/// The state of a Node that starts at zero: one block, value-initialised by
/// the Node's constructor (a zero-fill, then the services' few non-zero
/// defaults) instead of a store per member. TIME is a base: its stand-in
/// where the profile leaves it out takes no byte (time_stamp.h).
struct NodeState : TimeStamp {
  const ParamStorage* storage_;
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
  ParamSave save_;                 ///< 1010h "save", running over passes of process()
  const CanControl* can_control_;  ///< MB2CO_FLASH; null: no bit rate, no filters
  /// MB2CO_FLASH, the device's other services' ranges (set_service_ranges).
  const CanIdRange* service_ranges_;
  uint8_t service_range_count_;
  uint32_t overflow_us_;   ///< last CAN overrun (8110h held until + kControllerEventHoldUs)
  uint32_t recovered_us_;  ///< last bus-off recovery (8140h likewise)
  /// Rows of 1016h, 1017h, 100Ch, 100Dh (sub 0), in this order.
  enum : uint8_t { k1016, k1017, k100C, k100D, kRows };
  uint16_t row_[kRows];
  uint16_t row_1010_;  ///< 1010h sub 1
  uint8_t node_id_;
  uint8_t next_node_id_;
  uint8_t power_on_node_id_;  ///< start()'s: the id of a reset node without saved parameters
  NmtReset pending_reset_;
  bool params_loaded_;
  /// Resets that found a damaged saved-parameter slot (CRC, limits; never
  /// decrements, saturates at 255).
  uint8_t storage_damage_count_;
  bool hb_lost_;
  bool life_lost_;
  /// A write changed what the node consumes: the next process() hands
  /// acceptance() to CanControl::set_filters.
  bool filters_stale_;
};

class Node : private NodeState {
 public:
  Node(ObjectDictionary& od, const CanSink& sink);

  /// Optional; without storage 1010h reads 0 and "save" is refused. With
  /// one, "save" is answered at once and runs over the next process() calls
  /// (ParamSave): 1010h/1 reads 0 until it ends, then 1 again; a save that
  /// failed raises EMCY 5530h (1001h bit 0 until a save succeeds). While it
  /// runs, "save" and "load" (1011h) are refused with 08000022h (Modbus:
  /// exception 06, busy) and a reset (NMT, request_reset) waits for its end.
  void set_storage(const ParamStorage* storage) { storage_ = storage; }
  const ParamStorage* storage() const { return storage_; }
  void set_reset_callback(ResetCallback cb, void* ctx) {
    reset_cb_ = cb;
    reset_ctx_ = ctx;
  }
  /// The port's controller settings (platform/device_port.h: a MB2CO_FLASH table,
  /// called with the sink's ctx). Set before start(): the filters follow from
  /// the first reset on.
  void set_can_control(const CanControl* control) { can_control_ = control; }
  const CanControl* can_control() const { return can_control_; }
  /// What the device's other services receive besides what the node
  /// consumes (the gateway's network service: every SDO response and
  /// heartbeat), added to acceptance(): ranges[0..count), a MB2CO_FLASH
  /// table outliving the node, count <= kMaxServiceRanges. Set before start().
  void set_service_ranges(const CanIdRange* ranges, uint8_t count) {
    service_ranges_ = ranges;
    service_range_count_ = count;
  }
  /// The frame sink of the node's port, for the device's other services.
  const CanSink& sink() const { return sink_; }
  /// Node id used from the next reset communication on (1..127). Called
  /// from the reset callback, it names the id of the reset under way
  /// instead (the communication area is restored once more for it, before
  /// the one boot-up): how an application's saved id wins over a pending
  /// one at a reset node.
  void set_node_id_for_next_reset(uint8_t node_id) { next_node_id_ = node_id; }
  /// The one policy of a device's own node id and bit rate entries (the
  /// gateway's 2000h/1-2, the I/O node's 2001h/1-2; their writes are
  /// NodeHandlers::node_id and ::bitrate: a written id in force from the
  /// next reset communication, a rate of 125, 250, 500 or 1000 kbit/s), for
  /// the device's reset callback. `*node_id_entry` becomes this reset's id:
  /// at a reset communication the id the node took (written since, or
  /// set_node_id_for_next_reset), at a reset node the saved one, or without
  /// saved parameters start()'s. False when that id is not the one the node
  /// runs with: the node then runs the communication area's reset once more
  /// for it, before its one boot-up, and the device does the rest of its
  /// reset then. True: the bit rate entry's value has reached the
  /// controller (CanControl::set_bitrate, before the boot-up) and the reset
  /// goes on. (The entry by reference: read only then, on the AVR its load
  /// is not held across the id's store.)
  bool take_node_id_and_bitrate(NmtReset kind, uint8_t* node_id_entry, const uint16_t& bitrate_kbit_entry);

  /// A reset as if by NMT command, carried out at the next process() (so that
  /// a response to the request that asked for it can still leave first).
  void request_reset(NmtReset kind) { pending_reset_ = kind; }
  /// An NMT command given by the device itself (a self-starting node enters
  /// operational without a master), with the same effects as on the bus.
  void local_nmt(NmtCommand command, uint32_t now_us);
  /// A 1010h save is still running (its answer has left; 1010h/1 reads 0).
  bool saving() const { return save_.running(); }
  /// True when the last reset found a valid saved-parameter image.
  bool params_loaded() const { return params_loaded_; }
  /// Resets that found a damaged saved-parameter slot (EMCY 5530h each time,
  /// active with 1001h bit 0 until a save succeeds). Never decrements.
  uint8_t storage_damage_count() const { return storage_damage_count_; }

  /// Power-on: defaults and saved parameters, boot-up, pre-operational.
  void start(uint8_t node_id, uint32_t now_us);
  void receive(const CanFrame& f, uint32_t now_us);
  void process(uint32_t now_us);
  /// When process() must run next: false when nothing is pending (only a
  /// frame handed in, or another input, makes work); else *at_us, the
  /// earliest time (wrap-safe, time_reached(); at most 2^31 us ahead) at
  /// which a timer of any service falls due, or now_us when work is waiting
  /// (a pending reset, filters to set, a refused send to retry, an OD change
  /// the TPDOs have not seen). Invariant, for a caller that sleeps: process()
  /// called at *at_us, or after any later input (receive(), an OD write, a
  /// reset request, on_controller_state()), does everything due; called
  /// earlier than that it changes nothing observable (but 1013h, the
  /// network clock, which reads the time of the last call). Valid after start()
  /// and after a process() at now_us or before; inputs since void it. Every
  /// timer service contributes (heartbeat producer, node/life guarding,
  /// heartbeat consumers, SYNC producer, TPDO inhibit and event timers,
  /// RPDO timeouts, EMCY inhibit, the controller EMCY hold times, the SDO
  /// server timeout). Not used on the AVR (its loop runs every pass).
  bool next_deadline(uint32_t now_us, uint32_t* at_us) const;
  /// The same, lowering `d` (for an owner that has timers of its own).
  void next_deadline(NextDeadline& d) const;
  /// How long 8110h and 8140h stay active after their event.
  static const uint32_t kControllerEventHoldUs = 1000000;
  /// While a save waits for a busy storage (ParamStorage::ready false), how
  /// often next_deadline() asks for process() (an EEPROM byte: 3.3 ms).
  static const uint32_t kSavePollUs = 500;
  /// The CAN port reports its controller (ControllerEvent bits; `passive`:
  /// error passive or bus-off now). EMCY (error register "communication"):
  /// 8110h on an overrun and 8140h on a recovery from bus-off, each cleared
  /// kControllerEventHoldUs later by process(); 8120h while passive. Same
  /// context as receive().
  void on_controller_state(uint8_t events, bool passive, uint32_t now_us);

  /// The one derivation of what the device must receive, as the OD
  /// configures it now (valid after start()), written to ranges[0..n)
  /// (room for kMaxAcceptanceRanges) and n returned: one exact range per
  /// standard id the node consumes (NMT 000h, SYNC 1005h, SDO request
  /// 600h+id, node guarding 700h+id, every valid standard RPDO COB-ID of
  /// 1400h-1403h/1, 700h+n for each heartbeat consumer of 1016h with a node
  /// 1..127 and a time; one may repeat another), then kTpdoRemoteRange where
  /// the TPDOs answer remote requests, then the service ranges. Frames
  /// outside them the device ignores, so a port may filter them out in
  /// hardware (CanControl::set_filters: the CAN ports, the simulator).
  uint8_t acceptance(CanIdRange* ranges) const;
  /// The most ids one range of a node's own admits (a port's choice of
  /// filters, avr::CanPortFor; a device with wider services says more).
  static constexpr uint16_t kWidestRange = profile::kTpdoRtr ? ids_in(kTpdoRemoteRange) : 1;

  NmtState nmt_state() const { return nmt_.state(); }
  uint8_t node_id() const { return node_id_; }
  ObjectDictionary& od() { return od_; }
  EmcyProducer& emcy() { return emcy_; }
  HeartbeatConsumer& heartbeat_consumer() { return hb_consumer_; }
  Tpdos& tpdos() { return tpdos_; }
  Rpdos& rpdos() { return rpdos_; }
  /// The node's SDO server: where the profile has block transfer
  /// (MB2CO_CONFIG_SDO_BLOCK), its domain objects and block transfer switch
  /// (SdoServer::set_domain, set_block_transfer).
  SdoServer& sdo_server() { return sdo_; }
  /// The network clock (TIME, 1013h; profile::kTime).
  TimeStamp& time() { return *this; }
  const TimeStamp& time() const { return *this; }

 private:
  friend struct NodeHandlers;  // the OD's handlers of the communication area (od_comm.h)
  SdoAbort on_hb_consumer_write(uint8_t sub, uint32_t value, bool apply);
  HookResult on_store_write(uint16_t index, uint32_t value, bool apply);
  void reset(NmtReset kind, uint32_t now_us);
  void enter(NmtState state);
  /// Side effects of a state change that already happened.
  void on_transition(NmtState before);
  void on_sync_event(uint8_t counter, uint32_t now_us);
  void update_guard_emcy();
  uint16_t guard_time_ms() const;
  uint8_t life_time_factor() const;
  void update_filters();
  void expire_controller_emcy(uint32_t now_us);
  void step_save();

  ObjectDictionary& od_;
  CanSink sink_;
};

}  // namespace canopen
}  // namespace mb2co
