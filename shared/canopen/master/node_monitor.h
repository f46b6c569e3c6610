// The master's watch over its nodes (CiA 301 §7.2.8.3.2): heartbeat
// consumption or node guarding, one of the two per node, and the boot-up
// message (700h+id, data 00h) of either. A NodeMonitor watches one node; a
// NodeMonitorTable<N> up to N (<= 127) and routes the 700h+id frames to them.
//
// Arming: a monitor raises "lost" only once it is armed, i.e. after the
// node's first heartbeat (heartbeat) or first guarding answer (guarding); a
// configured node never heard from stays kLinkWaiting and raises nothing but
// its boot-up. A node configured for neither raises nothing at all.
//
// One protocol per node (CiA 301): a guarded node's every 1-byte frame on
// 700h+id is taken as a guarding answer (a heartbeat there would show as
// toggle errors), a heartbeat-watched node gets no RTRs.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"

namespace mb2co {
namespace canopen {

/// The NMT state a monitor reports before it has heard one.
const uint8_t kNodeStateUnknown = 0xFF;

enum MonitorEvent : uint8_t {
  kMonitorNodeLost = 1,      ///< consumer time (heartbeat) or life time (guarding) ran out
  kMonitorNodeBack = 2,      ///< heard again after kMonitorNodeLost (a boot-up counts)
  kMonitorStateChanged = 3,  ///< the node reported another NMT state (old → new)
  kMonitorBootUp = 4,        ///< boot-up message: the node was reset (new state 00h)
  kMonitorToggleError = 5,   ///< a guarding answer with the toggle bit not alternating
};

/// How the monitors report (a function and its context, like CanSink).
/// `old_state`/`new_state` are NMT state bytes (kNmtPreOperational, ...,
/// kNodeStateUnknown); both equal the current state for lost/back/toggle.
/// Called from inside on_frame()/process(); it must not call them again.
struct MonitorListener {
  void (*on_event)(void* ctx, uint8_t node_id, MonitorEvent event, uint8_t old_state, uint8_t new_state);
  void* ctx;
};

enum MonitorLink : uint8_t {
  kLinkOff = 0,  ///< not configured
  kLinkWaiting,  ///< configured, not armed yet (nothing heard, or a boot-up since)
  kLinkAlive,    ///< armed and in time
  kLinkLost,     ///< armed, then the time ran out
};

/// One node's monitor. Plain data; value-initialised (= {}) it is kLinkOff.
class NodeMonitor {
 public:
  /// Heartbeat consumption: the node produces every `producer_ms` (its
  /// 1017h, kept for the master that configures the node) and is lost when
  /// `consumer_ms` pass without one (CiA 301: consumer time > producer
  /// time). False, monitor unchanged, for node id 0 or > 127, producer_ms 0
  /// or consumer_ms <= producer_ms. Starts over: kLinkWaiting.
  bool watch_heartbeat(uint8_t node_id, uint16_t producer_ms, uint16_t consumer_ms);
  /// Node guarding: an RTR on 700h+id every `guard_ms`; lost when no valid
  /// answer came for guard_ms × life_factor (the node's 100Ch × 100Dh).
  /// False for node id 0 or > 127, guard_ms 0 or life_factor 0. The first
  /// RTR leaves at the next process(). Starts over: kLinkWaiting.
  bool watch_guarding(uint8_t node_id, uint16_t guard_ms, uint8_t life_factor);
  /// Back to kLinkOff (no frames, no events).
  void unwatch() { *this = NodeMonitor(); }

  /// A frame on 700h + node_id (others are ignored: false). Heartbeat,
  /// guarding answer or boot-up; events go to `listener`.
  bool on_frame(const CanFrame& f, uint32_t now_us, const MonitorListener& listener);
  /// Sends due guarding RTRs and raises "lost" when a time ran out.
  void process(uint32_t now_us, const CanSink& sink, const MonitorListener& listener);
  /// Lowers `d` to this monitor's next RTR or time-out.
  void next_deadline(NextDeadline& d) const;

  uint8_t node_id() const { return node_id_; }
  MonitorLink link() const { return static_cast<MonitorLink>(link_); }
  bool guarding() const { return guarding_; }
  /// Last NMT state heard (kNodeStateUnknown before any; 00h after a boot-up).
  uint8_t state() const { return state_; }
  uint16_t producer_ms() const { return guarding_ ? 0 : producer_ms_; }
  /// Guarding answers with a wrong toggle bit (never decrements, saturates).
  uint8_t toggle_errors() const { return toggle_errors_; }
  /// Guarding RTRs the port refused (retried at the next process()).
  uint8_t send_failures() const { return send_failures_; }

 private:
  void emit(const MonitorListener& l, MonitorEvent e, uint8_t old_state) const {
    if (l.on_event != nullptr) l.on_event(l.ctx, node_id_, e, old_state, state_);
  }
  void heard(uint8_t state, uint32_t now_us, const MonitorListener& l);
  bool start(uint8_t node_id, uint16_t time_ms, bool guarding);

  uint32_t deadline_us_ = 0;  ///< consumer time or life time runs out (armed only)
  uint32_t next_rtr_us_ = 0;  ///< guarding: the next RTR is due
  uint32_t life_us_ = 0;      ///< consumer time or guard time × life factor, in µs
  uint16_t guard_ms_ = 0;     ///< guarding: RTR period
  uint16_t producer_ms_ = 0;  ///< heartbeat: the node's 1017h
  uint8_t node_id_ = 0;
  uint8_t link_ = kLinkOff;  ///< MonitorLink
  uint8_t state_ = kNodeStateUnknown;
  uint8_t toggle_errors_ = 0;
  uint8_t send_failures_ = 0;
  bool guarding_ = false;
  bool toggle_ = false;   ///< guarding: toggle bit the next answer must carry
  bool rtr_due_ = false;  ///< guarding: send at the next process() (just armed)
};

/// Monitors for up to `Capacity` nodes (1..127), each added once by node id.
/// The events of all go to one listener. Cost: on_frame is O(Capacity).
template <uint8_t Capacity>
class NodeMonitorTable {
  static_assert(Capacity >= 1 && Capacity <= 127, "1..127 nodes");

 public:
  void set_listener(const MonitorListener& listener) { listener_ = listener; }
  /// The monitor of `node_id`, a free one (configure it with watch_*), or
  /// nullptr when the table is full or node_id is not 1..127.
  NodeMonitor* monitor(uint8_t node_id) {
    if (node_id == 0 || node_id > 127) return nullptr;
    NodeMonitor* free_slot = nullptr;
    for (NodeMonitor& m : mon_) {
      if (m.node_id() == node_id) return &m;
      if (free_slot == nullptr && m.link() == kLinkOff) free_slot = &m;
    }
    return free_slot;
  }
  /// The configured monitor of `node_id`, or nullptr.
  const NodeMonitor* find(uint8_t node_id) const {
    for (const NodeMonitor& m : mon_) {
      if (m.link() != kLinkOff && m.node_id() == node_id) return &m;
    }
    return nullptr;
  }
  /// A received frame; true if a monitor consumed it (701h..77Fh only).
  bool on_frame(const CanFrame& f, uint32_t now_us) {
    if (f.extended() || f.id < 0x701u || f.id > 0x77Fu) return false;
    for (NodeMonitor& m : mon_) {
      if (m.link() != kLinkOff && m.on_frame(f, now_us, listener_)) return true;
    }
    return false;
  }
  void process(uint32_t now_us, const CanSink& sink) {
    for (NodeMonitor& m : mon_) m.process(now_us, sink, listener_);
  }
  void next_deadline(NextDeadline& d) const {
    for (const NodeMonitor& m : mon_) m.next_deadline(d);
  }
  /// Monitors now in kLinkLost.
  uint8_t lost_count() const {
    uint8_t n = 0;
    for (const NodeMonitor& m : mon_) n = static_cast<uint8_t>(n + (m.link() == kLinkLost ? 1 : 0));
    return n;
  }

 private:
  NodeMonitor mon_[Capacity] = {};
  MonitorListener listener_ = {nullptr, nullptr};
};

}  // namespace canopen
}  // namespace mb2co
