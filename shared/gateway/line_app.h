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

#include "canopen/clock.h"
#include "canopen/heartbeat_consumer.h"
#include "canopen/node.h"
#include "canopen/od.h"
#include "gateway/gateway_od.h"
#include "gateway/line_values.h"
#include "gateway/stop_cause.h"

namespace mb2co {
namespace gateway {

/// A neighbour whose RUN state is not known: no heartbeat, or alive but no
/// TPDO1 heard yet (kNeighbourNotHeard); neither alive nor none. Its LED blinks.
inline bool neighbour_shown_unknown(uint8_t status) {
  return status != kNeighbourAlive && status != kNeighbourNone;
}

/// Plain data without initialisers: its owner value-initialises it (all
/// zero, which a static object on the Uno is without code), then init().
class LineApp {
 public:
  /// Blink half-period of an LED showing an unknown neighbour.
  static const uint32_t kBlinkHalfPeriodUs = 250000;

  /// `values` is the value block of `od` (the gateway OD): the application
  /// reads and writes its entries there directly (no lookup, no flash access
  /// per pass); PDO-mappable ones through ObjectDictionary::put(), which
  /// tells the OD (and so the TPDOs) when one changed.
  void init(canopen::ObjectDictionary* od, od::GatewayValues* values);
  /// Power-on at `now_us`: the Modbus watchdog runs from here, so a station
  /// whose PC never comes is stopped with cause kCausePcSilent like one whose
  /// PC fell silent.
  void start(uint32_t now_us) {
    last_request_us_ = now_us;
    watchdog_armed_ = true;
  }
  /// After every reset: derives neighbours, RPDO COB-IDs and 1016h from node
  /// id and topology unless 2000h/7 says the stored configuration applies.
  void on_reset(uint8_t node_id);
  void on_heartbeat(uint8_t node_id, canopen::HbEvent event);
  void on_rpdo(uint8_t n, uint32_t now_us);
  /// The PC wrote the RUN command `value` (0..1, checked by the OD): 0
  /// acknowledges a latched stop.
  void on_run_command(uint8_t value) {
    if (value == 0) stop_latched_ = false;
  }
  /// Samples raw button levels (Button bits, 1 = pressed), updates the OD,
  /// returns the LED bits to drive now. `modbus_requests` counts the
  /// requests the slave has accepted (for the watchdog).
  uint8_t process(uint32_t now_us, uint8_t raw_buttons, uint8_t nmt_state, uint16_t modbus_requests);
  /// Lowers `d` to when process() with the same raw buttons must run next
  /// (Gateway::next_deadline): now when it would write something else than
  /// it wrote last (the node changed state or reset, a callback changed a
  /// neighbour or latched a stop, a Modbus request came, the blink phase
  /// turned); else a debounce running out (2000h/6), the Modbus watchdog
  /// (2000h/9) and the next blink phase while a neighbour is unknown.
  void next_deadline(NextDeadline& d, uint8_t nmt_state, uint16_t modbus_requests) const;
#if MB2CO_CONFIG_TIME
  /// The station's clock is common (TIME set it): network time minus local
  /// time (TimeStamp::offset_us), else 0. The 2300h stamps are the local
  /// time plus this: on the common clock (1013h's scale) once it is set, so
  /// that another station's stamp can be subtracted from them.
  void set_stamp_offset(uint32_t offset_us) {
    stamp_offset_us_ = offset_us;
  }
#endif

 private:
#if MB2CO_CONFIG_TIME
  uint32_t stamp(uint32_t local_us) const {
    return local_us + stamp_offset_us_;
  }
  uint32_t stamp_offset_us_;
#else
  static uint32_t stamp(uint32_t local_us) {
    return local_us;
  }
#endif
  /// Out of line: four call sites.
  __attribute__((noinline)) void latch_stop(StopCause cause);
  void neighbour_config(uint8_t node_id, uint8_t* prev, uint8_t* next) const;

  canopen::ObjectDictionary* od_;
  od::GatewayValues* v_;
  uint32_t raw_since_us_[3];  ///< when each raw level last changed
  uint32_t last_request_us_;
  uint16_t prev_stop2_seen_;
  uint16_t requests_seen_;
  uint8_t raw_;     ///< last raw levels
  uint8_t stable_;  ///< debounced levels
  uint8_t leds_;
  bool prev_stop2_known_;  ///< a baseline of the previous STOP2 counter (see kNeighbourNotHeard)
  bool stop_latched_;
  /// Modbus watchdog: armed at power-on and by every request; silence for
  /// 2000h/9 ms latches one stop (2000h/9 = 0: a station without a PC).
  bool watchdog_armed_;
};

}  // namespace gateway
}  // namespace mb2co
