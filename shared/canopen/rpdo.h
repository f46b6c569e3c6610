// The node's receive PDOs 1–4 (1400h–1403h communication, 1600h–1603h
// mapping). Types 0–240 are synchronous (the data is applied at the next
// SYNC), 254/255 are applied on reception. Length errors raise EMCY 8210h
// (too short: not processed) or 8220h (too long: processed); an event timer
// (sub 5, ms) that elapses without reception raises EMCY 8250h.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/emcy_producer.h"
#include "canopen/od.h"
#include "canopen/od_comm.h"
#include "canopen/pdo_map.h"

namespace mb2co {
namespace canopen {

/// Told after an RPDO's data reached the OD (0-based PDO number).
typedef void (*RpdoCallback)(void* ctx, uint8_t n);

/// Members that start at zero have no initialisers: the owner (NodeState)
/// is value-initialised, which zero-fills it in one go.
class Rpdos {
 public:
  void init(ObjectDictionary* od, EmcyProducer* emcy);
  void set_callback(RpdoCallback cb, void* ctx) {
    cb_ = cb;
    cb_ctx_ = ctx;
  }
  /// Returns true if `f` matched a valid RPDO (consumed, even when rejected).
  bool on_frame(const CanFrame& f, uint32_t now_us);
  /// Applies buffered synchronous RPDOs.
  void on_sync();
  /// RPDO event-timer monitoring.
  void process(uint32_t now_us);
  /// Lowers `d` to the earliest event timer (timeout) running out.
  void next_deadline(NextDeadline& d) const;
  /// Leaving operational: timeouts stop, buffers are dropped.
  void stop();
  /// 140xh/1 of RPDO n (0..kPdoCount-1) as the OD holds it now.
  uint32_t cob_id(uint8_t n) const { return comm(n, 1); }  // row 1: sub 1
  /// Validates writes to 1400h–1403h and 1600h–1603h (OD hook).
  SdoAbort on_write(uint16_t index, uint8_t sub, const uint8_t* data, bool apply);

 private:
  struct State {
    uint32_t deadline_us;
    uint8_t buffer[8];
    uint8_t flags;
  };
  enum : uint8_t { kBuffered = 0x01, kMonitoring = 0x02, kTimedOut = 0x04, kShort = 0x08, kLong = 0x10 };
  uint16_t comm_row(uint8_t n) const { return static_cast<uint16_t>(rec_.comm0 + n * 5u); }
  /// Value of row `k` of PDO n's communication record (out of line: many callers).
  uint32_t comm(uint8_t n, uint8_t k) const;
  uint16_t map_row(uint8_t n) const { return static_cast<uint16_t>(rec_.map0 + n * rec_.map_stride); }
  void apply(uint8_t n, const uint8_t* data);
  void update_length_errors();

  ObjectDictionary* od_;
  EmcyProducer* emcy_;
  PdoRecords rec_;  ///< rows of 1400h and 1600h sub 0, the mapping stride
  State st_[kPdoCount];
  RpdoCallback cb_;
  void* cb_ctx_;
};

}  // namespace canopen
}  // namespace mb2co
