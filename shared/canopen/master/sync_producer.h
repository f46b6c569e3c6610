// The master's SYNC producer (CiA 301 §7.2.5): a SYNC on the COB-ID of 1005h
// every 1006h µs, with the counter of 1019h. Not the node core's Sync
// (canopen/sync.h): that one reads 1005h/1006h/1019h from a node's Object
// Dictionary and is validated by its write hooks; a master configures its
// producer directly and owns no OD.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"

namespace mb2co {
namespace canopen {

class SyncProducer {
 public:
  /// `cob_id`: 1005h (bits 0-10 used; bit 29, a 29-bit id, is refused);
  /// `period_us`: 1006h, 0 = stopped; `overflow`: 1019h, 0 = SYNC without
  /// counter (0 data bytes), 2..240 = the counter runs 1..overflow and is the
  /// frame's one data byte. False, producer unchanged, for 1019h = 1 or >
  /// 240 or a 29-bit id. The period starts at the next process(); the
  /// counter starts at 1.
  bool configure(uint32_t cob_id, uint32_t period_us, uint8_t overflow);
  /// Sends the SYNC when its period elapsed; true when one was sent now
  /// (*counter = its counter, 0 without one; counter may be nullptr). A
  /// SYNC the port refused is counted and not repeated (the next one keeps
  /// the period: SYNC is a time base, a late one is worse than none).
  bool process(uint32_t now_us, const CanSink& sink, uint8_t* counter = nullptr);
  /// Lowers `d` to the next SYNC (now while the period has to start).
  void next_deadline(NextDeadline& d) const;

  uint16_t cob_id() const { return cob_id_; }
  uint32_t period_us() const { return period_us_; }
  uint8_t overflow() const { return overflow_; }
  /// SYNCs the port refused (never decrements, saturates).
  uint16_t send_failures() const { return send_failures_; }

 private:
  uint32_t period_us_ = 0;
  /// Start of the current period: elapsed time is compared, not a deadline,
  /// so a 1006h of 2^31 µs or more works (process() runs more often).
  uint32_t period_start_us_ = 0;
  uint16_t cob_id_ = 0x080;
  uint16_t send_failures_ = 0;
  uint8_t overflow_ = 0;
  uint8_t counter_ = 0;  ///< last counter sent (0: none yet)
  bool restart_ = true;
};

}  // namespace canopen
}  // namespace mb2co
