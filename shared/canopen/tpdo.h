// The node's transmit PDOs 1–4 (1800h–1803h communication, 1A00h–1A03h
// mapping). Transmission types: 0 (synchronous acyclic: at SYNC after a
// change), 1–240 (every n-th SYNC), 252 (sampled at SYNC, sent on RTR), 253
// (built and sent on RTR), 254/255 (event: change of mapped data or event
// timer, spaced by the inhibit time in 100 µs units).
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/od.h"
#include "canopen/od_comm.h"
#include "canopen/pdo_map.h"
#include "profiles/profile.h"

namespace mb2co {
namespace canopen {

/// Members that start at zero have no initialisers: the owner (NodeState)
/// is value-initialised, which zero-fills it in one go.
class Tpdos {
 public:
  void init(ObjectDictionary* od);
  /// Entering operational: event-driven TPDOs send their current data.
  void on_operational();
  /// Asks TPDO `n` (0-based) to send at the next opportunity (event types).
  void request(uint8_t n);
  /// A SYNC with `counter` (0 if the SYNC has none).
  void on_sync(uint8_t counter, const CanSink& sink, uint32_t now_us);
  /// An RTR on one of our COB-IDs; returns true if it was for a TPDO.
  /// Defined only where the profile has it (profile::kTpdoRtr, every host
  /// build; callers test the constant): the Uno's CAN port admits no remote
  /// frames for TPDOs (RTR is deprecated, CiA AN 802), so its image leaves
  /// the answer and type 252's sampling out; types 252/253 are accepted
  /// there and never transmit, as before.
  bool on_rtr(const CanFrame& f, const CanSink& sink, uint32_t now_us);
  /// Builds TPDO `n` from its mapping and sends it now, whatever its
  /// transmission type and timers say (the lab's pdo_send). kSendNowInvalid
  /// when its COB-ID is marked invalid or nothing is mapped.
  enum SendNow : uint8_t { kSentNow, kSendNowInvalid, kSendNowRefused };
  SendNow send_now(uint8_t n, const CanSink& sink, uint32_t now_us);
  /// Event-driven transmissions (change of data, event timer, inhibit).
  void process(uint32_t now_us, const CanSink& sink);
  /// Lowers `d` to when process() does something again: now after an OD
  /// change or for a pending event PDO the inhibit time lets go (a refused
  /// send is retried), else its inhibit and event timers.
  void next_deadline(NextDeadline& d) const;
  /// Validates writes to 1800h–1803h and 1A00h–1A03h (OD hook).
  SdoAbort on_write(uint16_t index, uint8_t sub, const uint8_t* data, bool apply);
  /// Frames the port refused (never decrements).
  uint16_t send_failures() const { return send_failures_; }
  /// TPDOs (bit n: TPDO n + 1) whose transmission type 255, "event-driven,
  /// device profile specific" in CiA 301, is the application's event: a
  /// change of their data does not send them; request(), the event timer
  /// and entering operational do (the I/O node: CiA 401's interrupt masks
  /// decide). Type 254 stays change of data. None until set. Without the
  /// profile's switch (profile::kProfileEvents) it does nothing.
  void set_profile_events(uint8_t pdos) {
#if MB2CO_CONFIG_PROFILE_EVENTS
    profile_events_ = pdos;
#else
    (void)pdos;
#endif
  }

 private:
  struct State {
    uint32_t inhibit_until_us;
    uint32_t event_deadline_us;
    uint8_t last[8];  ///< last sent (254/255, 0) or sampled (252) payload
    uint8_t last_len;
    uint8_t sync_count;  ///< SYNCs since the last cyclic transmission
    uint8_t flags;
  };
  enum : uint8_t {
    kPending = 0x01,  ///< send when inhibit time allows
    kInhibiting = 0x02,
    kEventTimer = 0x04,    ///< event timer armed
    kSyncStarted = 0x08,   ///< SYNC start value reached (1–240); 252: a sample is held
    kSent = 0x10,          ///< `last` holds a transmitted payload
    kEventType = 0x20,     ///< valid with type 254/255 at the last full look (process)
    kEventWritten = 0x40,  ///< 1800h/5 written: the timer restarts at the next process()
  };
  bool valid(uint8_t n, uint32_t* cob) const;
  bool send(uint8_t n, uint32_t cob, const uint8_t* data, uint8_t len, const CanSink& sink, uint32_t now_us);
  /// Event timer of PDO n from `now_us` with its 1800h/5 (0: off).
  void start_event_timer(uint8_t n, uint32_t now_us);
  /// Builds PDO n's payload from the OD and sends it (one copy for SYNC and
  /// RTR).
  void build_and_send(uint8_t n, uint32_t cob, const CanSink& sink, uint32_t now_us);
  uint16_t comm_row(uint8_t n) const {
    return static_cast<uint16_t>(rec_.comm0 + n * 6u);
  }
  /// Value of row `k` of PDO n's communication record (out of line: many callers).
  uint32_t comm(uint8_t n, uint8_t k) const;
  uint16_t map_row(uint8_t n) const {
    return static_cast<uint16_t>(rec_.map0 + n * rec_.map_stride);
  }
#if MB2CO_CONFIG_PROFILE_EVENTS
  /// Whether a change of PDO n's data sends it (type 254/255).
  bool change_sends(uint8_t n, uint8_t type) const {
    return type != 255 || !((profile_events_ >> n) & 1u);
  }
#endif

  ObjectDictionary* od_;
  PdoRecords rec_;  ///< rows of 1800h and 1A00h sub 0, the mapping stride
  State st_[kPdoCount];
  uint16_t send_failures_;
  uint16_t seen_revision_;  ///< od_->revision() at the last process()
#if MB2CO_CONFIG_PROFILE_EVENTS
  uint8_t profile_events_;  ///< set_profile_events(); init() leaves it
#endif
};

}  // namespace canopen
}  // namespace mb2co
