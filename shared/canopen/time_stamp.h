// TIME (CiA 301 §7.2.6; 1012h) and the high-resolution time stamp (1013h):
// the network clock a node keeps. The core never reads a clock: it is
// handed local time (now_us, the port's wrapping 32-bit µs clock) and keeps
// only how the network clock runs against it.
//
// The network clock, as 1013h reads it, counts µs since the CANopen epoch
// (1984-01-01 00:00, TIME_OF_DAY's day 0) modulo 2^32: the time scale of a
// TIME frame (ms after midnight + days) in 1013h's unit, so a TIME frame and
// a 1013h write set the same clock and a difference of two stamps is a
// duration across midnight too (CiA 301 leaves 1013h's epoch open).
//
// Where CiA 301 leaves a choice this does what CANopenNode's 301/CO_TIME.c
// does: 1012h bit 31 = consumer, bit 30 = producer, bits 0-10 the CAN-ID
// (bit 29, 29-bit ids: refused; a restricted id: refused, 06090030h); a
// frame is taken only with exactly 6 data bytes (others are ignored, no
// EMCY) and only in pre-operational or operational; the 28 bits of ms are
// masked from the 32 sent; the producer's period is the application's (not
// an OD entry). Unlike CANopenNode a write of 1012h takes effect at once
// (the node's filters follow), not at the next reset communication.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/od.h"
#include "canopen/sdo_abort.h"
#include "canopen/time_of_day.h"
#include "profiles/profile.h"

namespace mb2co {
namespace canopen {

/// 1012h bits (CANopenNode CO_TIME.c: isConsumer, isProducer).
const uint32_t kTimeConsumer = 0x80000000u;
const uint32_t kTimeProducer = 0x40000000u;

#if MB2CO_CONFIG_TIME
/// Members start at zero (the owner value-initialises it); init() after
/// every reset. Same context as Node::receive()/process(). The Node holds
/// it as a base of its state (Node::time()), so that the stand-in below
/// costs no byte where the profile leaves TIME out.
class TimeStamp {
 public:
  /// How often the producer sends TIME by default (CANopenNode: the
  /// application's producerInterval_ms).
  static const uint16_t kDefaultProducerPeriodMs = 1000;

  /// After a reset: the rows of 1012h and 1013h (restored to their
  /// defaults: the clock is unset until the next TIME or 1013h write).
  __attribute__((noinline)) void init(ObjectDictionary* od, uint32_t now_us);
  /// A TIME frame (COB-ID of 1012h, consumer bit set, 6 bytes) sets the
  /// network clock to the time it carries at `now_us`, its arrival: true
  /// when `f` was one (consumed). `allowed`: pre-operational or operational.
  __attribute__((noinline)) bool on_frame(const CanFrame& f, uint32_t now_us, bool allowed);
  /// Brings 1013h's value to the network time at `now_us`. Called before
  /// every frame is handled and in every process(): a read of 1013h (SDO,
  /// Modbus, TPDO) gives the time of the request, and a write of 1013h
  /// (SDO, RPDO, Modbus) then sets the clock to the value at that instant.
  __attribute__((noinline)) void refresh(uint32_t now_us);
  /// Producer (1012h bit 30, profile::kTimeProducer): a TIME frame every
  /// producer period while `allowed`.
  void process(uint32_t now_us, bool allowed, const CanSink& sink);
  void next_deadline(NextDeadline& d, bool allowed) const;
  /// Validates writes of 1012h and 1013h (its handlers, NodeHandlers::time_cob_id and ::time_stamp).
  SdoAbort on_write(uint16_t index, const uint8_t* data, bool apply);

  /// The network clock at `now_us` (µs since 1984-01-01, mod 2^32); the
  /// local clock plus 0 while unset.
  uint32_t network_us(uint32_t now_us) const { return now_us + offset_us(); }
  /// Network time minus local time (mod 2^32): the state that makes the
  /// local clock the network's.
  uint32_t offset_us() const;
  /// A TIME frame or a 1013h write set the clock since the last reset.
  bool clock_set() const { return set_; }
  /// The network time at which the clock was last set (a TIME frame's
  /// time, or the value a 1013h write gave); meaningful while clock_set().
  /// How long ago: network_us(now) - set_at_us(), the time the local clock
  /// has run on its own (its drift against the producer's grows with it).
  uint32_t set_at_us() const { return set_at_us_; }
  /// 1012h: consumer bit set and a valid standard id (what to receive).
  bool consuming() const { return (cob() & kTimeConsumer) != 0; }
  uint16_t can_id() const { return static_cast<uint16_t>(cob() & 0x7FFu); }
#if MB2CO_CONFIG_TIME >= 2
  void set_producer_period_ms(uint16_t ms) {
    period_ms_ = ms;
  }
  /// The network time as TIME_OF_DAY at `now_us` (valid while the clock
  /// advanced less than 71 minutes since the last TIME, 1013h write or
  /// production: the producer runs more often).
  TimeOfDay time_of_day(uint32_t now_us) const;
  /// The application sets the network clock (a producer that has a real
  /// clock: the host's, handed in; the core reads none).
  void set_time_of_day(const TimeOfDay& t, uint32_t now_us);
#endif

 private:
  uint32_t cob() const {
    return load(cob_);
  }
  uint32_t stamp() const {
    return load(cob_ + 4);
  }
  void set_stamp(uint32_t v) {
    store(cob_ + 4, v);
  }
  /// An OD value as stored: 32 bits little-endian (od.h), as both targets are.
  static uint32_t load(const uint8_t* p);
  static void store(uint8_t* p, uint32_t v);

  /// The value of 1012h in the OD's value block, 1013h's the 4 bytes after
  /// it (consecutive rows of the same size; fixed for the OD's life): read
  /// and written in place, untracked (the clock running on is no change
  /// for the TPDOs). A write through the OD (SDO, RPDO, Modbus) lands there
  /// too, after the hook.
  uint8_t* cob_;
  /// Local time at which 1013h's value was the network time: network(t) =
  /// 1013h + (t - at_us_), exact across the 2^32 wrap (both are mod 2^32).
  uint32_t at_us_;
  uint32_t set_at_us_;  ///< network µs of the last set (set_at_us())
  bool set_;
#if MB2CO_CONFIG_TIME >= 2
  /// The producer's day: `day_` at network µs `day_base_us_` (the TIME_OF_DAY
  /// the clock was last set to or produced; 1013h alone cannot say the day).
  TimeOfDay day_;
  uint32_t day_base_us_;
  uint32_t sent_us_;    ///< local time of the last TIME produced
  uint16_t period_ms_;  ///< 0: kDefaultProducerPeriodMs
  bool producing_;      ///< the period runs (else the next process() sends at once)
#endif
};
#else
/// The stand-in where the profile leaves TIME out: no rows, no state, no
/// code (an empty base of the Node's state takes no byte).
class TimeStamp {
 public:
  void init(ObjectDictionary*, uint32_t) {}
  bool on_frame(const CanFrame&, uint32_t, bool) { return false; }
  void refresh(uint32_t) {}
  void process(uint32_t, bool, const CanSink&) {}
  void next_deadline(NextDeadline&, bool) const {}
  SdoAbort on_write(uint16_t, const uint8_t*, bool) { return kSdoOk; }
  uint32_t network_us(uint32_t now_us) const { return now_us; }
  uint32_t offset_us() const { return 0; }
  bool clock_set() const { return false; }
  uint32_t set_at_us() const { return 0; }
  bool consuming() const { return false; }
  uint16_t can_id() const { return 0; }
};
#endif

}  // namespace canopen
}  // namespace mb2co
