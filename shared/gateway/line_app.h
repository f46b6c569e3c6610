// The RUN/STOP2 line application of one station (seed 000 §10, DESIGN §6),
// configured by OD entries and PDOs only:
//  - buttons START, STOP, STOP2 debounced (2000h/6); press counters; a STOP2
//    press increments the STOP2 event counter 2100h/3 (a counter, never lost);
//  - RUN state 2100h/2 = PC's RUN command 2100h/1 unless a stop is latched:
//    STOP or STOP2 pressed here, or a new STOP2 event of the previous station.
//    The latch clears when the PC writes RUN command 0 (it saw the stop);
//  - neighbours (previous/next by node id, chain or ring: 2000h/3, 2000h/4)
//    by RPDO1/RPDO2 from their TPDO1 and by heartbeat consumer 1016h: a lost
//    neighbour is "unknown" (LED blinking), never "running";
//  - LEDs RUN-self, RUN-prev, RUN-next, lab LED (6200h/1 bit 0);
//  - latency-lab timestamps 2300h.
#pragma once
#include <stdint.h>

#include "canopen/heartbeat_consumer.h"
#include "canopen/node.h"
#include "canopen/od.h"
#include "gateway/gateway_od.h"

namespace mb2co {
namespace gateway {

enum Button : uint8_t { kStart = 0x01, kStop = 0x02, kStop2 = 0x04 };
enum Led : uint8_t { kLedRunSelf = 0x01, kLedRunPrev = 0x02, kLedRunNext = 0x04, kLedLab = 0x08 };
enum StopCause : uint8_t {
  kCauseNone = 0,
  kCauseStopButton = 1,
  kCauseStop2Here = 2,
  kCauseStop2Previous = 3,
  kCausePcSilent = 4,  ///< no Modbus request for the watchdog time (2000h/9)
};
enum NeighbourStatus : uint8_t { kNeighbourUnknown = 0, kNeighbourAlive = 1, kNeighbourNone = 2 };

/// Plain data without initialisers: its owner value-initialises it (all
/// zero, which a static object on the Uno is without code), then init().
class LineApp {
 public:
  /// Blink half-period of an LED showing an unknown neighbour.
  static const uint32_t kBlinkHalfPeriodUs = 250000;

  /// `values` is the value block of `od` (the gateway OD): the application
  /// reads and writes its entries there directly (no lookup, no flash access
  /// per pass) and tells the OD when it changed one (ObjectDictionary::touch).
  void init(canopen::ObjectDictionary* od, od::GatewayValues* values);
  /// After every reset: derives neighbours, RPDO COB-IDs and 1016h from node
  /// id and topology unless 2000h/7 says the stored configuration applies.
  void on_reset(uint8_t node_id);
  void on_heartbeat(uint8_t node_id, canopen::HbEvent event);
  void on_rpdo(uint8_t n, uint32_t now_us);
  /// Validates application writes (RUN command); 0 or an SDO abort code.
  uint32_t on_run_command(uint8_t value);
  /// Samples raw button levels (Button bits, 1 = pressed), updates the OD,
  /// returns the LED bits to drive now. `modbus_requests` counts the
  /// requests the slave has accepted (for the watchdog).
  uint8_t process(uint32_t now_us, uint8_t raw_buttons, uint8_t nmt_state, uint16_t modbus_requests);

 private:
  /// Out of line: four call sites (-10 B on the Uno).
  __attribute__((noinline)) void latch_stop(StopCause cause);
  void neighbour_config(uint8_t node_id, uint8_t* prev, uint8_t* next) const;

  /// Stores `value` into a PDO-mappable entry of the value block, telling
  /// the OD (and so the TPDOs) when it changed (ObjectDictionary::touch).
  /// Entries no PDO can map are assigned directly.
  template <class T, class V>
  void put(T& entry, V value) {
    const T v = static_cast<T>(value);
    if (entry == v) return;
    entry = v;
    od_->touch();
  }

  canopen::ObjectDictionary* od_;
  od::GatewayValues* v_;
  uint32_t raw_since_us_[3];  ///< when each raw level last changed
  uint32_t last_request_us_;
  uint16_t prev_stop2_seen_;
  uint16_t requests_seen_;
  uint8_t raw_;               ///< last raw levels
  uint8_t stable_;            ///< debounced levels
  uint8_t leds_;
  bool prev_stop2_known_;     ///< a baseline of the previous STOP2 counter
  bool stop_latched_;
  /// Modbus watchdog: armed by the first request, so a station configured
  /// without a PC is not stopped; a silent PC then latches a stop.
  bool watchdog_armed_;
};

}  // namespace gateway
}  // namespace mb2co
