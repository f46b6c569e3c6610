// SYNC consumer and producer (CiA 301 §7.2.5; 1005h, 1006h, 1019h). The
// producer (1005h bit 30) sends a SYNC every 1006h µs; both a received and a
// produced SYNC are reported to the PDOs as one event with its counter.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/od.h"

namespace mb2co {
namespace canopen {

/// Members that start at zero have no initialisers: the owner (NodeState)
/// is value-initialised, which zero-fills it in one go.
class Sync {
 public:
  enum Result : uint8_t { kNotSync = 0, kSyncEvent, kSyncLengthError };

  void init(ObjectDictionary* od);
  /// A frame with the SYNC COB-ID: kSyncEvent (counter in *counter, 0 when
  /// the SYNC has none), or kSyncLengthError (EMCY 8240h) when its length does
  /// not match 1019h. Other frames: kNotSync.
  Result on_frame(const CanFrame& f, uint8_t* counter);
  /// Producer: true when a SYNC was sent now (*counter as for on_frame).
  bool process(uint32_t now_us, bool allowed, const CanSink& sink, uint8_t* counter);
  /// Lowers `d` to the producer's next SYNC (or its restart: now).
  void next_deadline(NextDeadline& d) const;
  /// Validates writes to 1005h, 1006h, 1019h (OD hook).
  SdoAbort on_write(uint16_t index, const uint8_t* data, bool apply);
  uint32_t cob_id() const { return od_->get(row_[k1005]) & 0x7FFu; }
  /// The producer's period starts afresh (e.g. back from NMT stopped, where
  /// process() was not called and the old deadline went stale).
  void restart() { restart_ = true; }

 private:
  /// Rows of 1005h, 1006h, 1019h (sub 0), in this order.
  enum : uint8_t { k1005, k1006, k1019, kRows };
  ObjectDictionary* od_;
  uint16_t row_[kRows];
  /// Start of the current period. Any 32-bit 1006h works as long as process()
  /// runs at least every 2^32 us - period (every pass does).
  uint32_t period_start_us_;
  uint8_t counter_;
  bool restart_;  ///< set by init() (every reset) before the first process()
};

}  // namespace canopen
}  // namespace mb2co
