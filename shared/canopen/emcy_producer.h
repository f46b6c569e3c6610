// EMCY producer (CiA 301 §7.2.7): keeps the set of active errors, the error
// register 1001h and the pre-defined error field 1003h, and sends an EMCY for
// every error that appears and an "error reset" (code 0000h) when the last one
// clears, spaced by the inhibit time 1015h.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/od.h"

namespace mb2co {
namespace canopen {

/// Emergency error codes used by mb2co (CiA 301 table 26).
enum EmcyCode : uint16_t {
  kEmcyErrorReset = 0x0000,
  kEmcyGeneric = 0x1000,
  kEmcyStorage = 0x5530,            ///< data storage (saved parameters damaged)
  kEmcyCanOverrun = 0x8110,         ///< CAN overrun (objects lost)
  kEmcyCanPassive = 0x8120,         ///< CAN in error passive mode
  kEmcyLifeGuard = 0x8130,          ///< life guard error or heartbeat error
  kEmcyBusOffRecovered = 0x8140,    ///< recovered from bus-off
  kEmcyPdoLength = 0x8210,          ///< PDO not processed due to length error
  kEmcyPdoLengthExceeded = 0x8220,  ///< PDO length exceeded
  kEmcySyncLength = 0x8240,         ///< unexpected SYNC data length
  kEmcyRpdoTimeout = 0x8250,        ///< RPDO timeout
};

/// Error register 1001h bits.
enum ErrorRegisterBit : uint8_t {
  kErrGeneric = 0x01,
  kErrCurrent = 0x02,
  kErrVoltage = 0x04,
  kErrTemperature = 0x08,
  kErrCommunication = 0x10,
  kErrDeviceProfile = 0x20,
  kErrManufacturer = 0x80,
};

/// Members that start at zero have no initialisers: the owner (NodeState)
/// is value-initialised, which zero-fills it in one go.
class EmcyProducer {
 public:
  static const uint8_t kMaxActive = 8;
  static const uint8_t kQueueLength = 4;

  void init(ObjectDictionary* od);
  /// An error condition appeared. Ignored when already active (one EMCY per
  /// appearance). `info` is the 5-byte manufacturer field (may be nullptr).
  void raise(uint16_t code, uint8_t register_bits, const uint8_t* info = nullptr);
  /// The error condition is gone; the last one to go sends "error reset".
  void clear(uint16_t code);
  /// raise() when `on`, else clear(): for conditions re-evaluated as a whole
  /// (one call site instead of two).
  void report(uint16_t code, bool on, uint8_t register_bits);
  /// Out of line: raise() and the node (controller EMCYs) ask it in several
  /// places, each an inlined loop otherwise (the Uno's flash).
  __attribute__((noinline)) bool active(uint16_t code) const;
  /// Sends queued EMCY frames when allowed and the inhibit time has passed.
  void process(uint32_t now_us, bool allowed, const CanSink& sink);
  /// Lowers `d` to when process(..., allowed, ...) must run next: the end
  /// of the inhibit time, or now for a queued EMCY that may leave.
  void next_deadline(NextDeadline& d, bool allowed) const;
  /// Validates writes to 1003h, 1014h, 1015h (OD hook).
  SdoAbort on_write(uint16_t index, uint8_t sub, const uint8_t* data, bool apply);
  /// Messages dropped because the queue was full (never decrements).
  uint16_t overflows() const { return overflows_; }

 private:
  void push_history(uint16_t code, const uint8_t* info);
  void enqueue(uint16_t code, const uint8_t* info);
  void update_register();

  struct Active {
    uint16_t code;
    uint8_t bits;
  };
  /// A queued EMCY: its payload as sent (code little-endian, error
  /// register, manufacturer field).
  struct Pending {
    uint8_t payload[8];
  };
  /// Rows of 1001h, 1003h, 1014h, 1015h (sub 0), in this order.
  enum : uint8_t { k1001, k1003, k1014, k1015, kRows };
  ObjectDictionary* od_;
  uint16_t row_[kRows];
  Active active_[kMaxActive];
  uint8_t active_count_;
  Pending queue_[kQueueLength];
  uint8_t queue_head_;
  uint8_t queue_count_;
  uint16_t overflows_;
  uint32_t inhibit_until_us_;
  bool inhibit_running_;
};

}  // namespace canopen
}  // namespace mb2co
