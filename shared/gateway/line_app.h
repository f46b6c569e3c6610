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

class LineApp {
 public:
  /// Blink half-period of an LED showing an unknown neighbour.
  static const uint32_t kBlinkHalfPeriodUs = 250000;

  void init(canopen::ObjectDictionary* od);
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
  void latch_stop(StopCause cause);
  void neighbour_config(uint8_t node_id, uint8_t* prev, uint8_t* next) const;
  uint16_t row(uint16_t index, uint8_t sub) const { return od_->find(index, sub); }
  bool led_for(uint16_t status_row, uint16_t run_row, uint32_t now_us) const;

  canopen::ObjectDictionary* od_ = nullptr;
  uint16_t r_run_cmd_ = 0, r_run_ = 0, r_stop2_count_ = 0, r_cause_ = 0, r_start_count_ = 0,
           r_stop_count_ = 0;
  uint16_t r_prev_run_ = 0, r_prev_stop2_ = 0, r_prev_status_ = 0, r_prev_id_ = 0;
  uint16_t r_next_run_ = 0, r_next_status_ = 0, r_next_id_ = 0;
  uint16_t r_inputs_ = 0, r_buttons_ = 0, r_leds_ = 0, r_outputs_ = 0, r_nmt_ = 0;
  uint16_t r_edge_us_ = 0, r_led_us_ = 0, r_remote_us_ = 0, r_debounce_ = 0, r_watchdog_ = 0;
  uint32_t raw_since_us_[3] = {0, 0, 0};  ///< when each raw level last changed
  uint8_t raw_ = 0;                        ///< last raw levels
  uint8_t stable_ = 0;                     ///< debounced levels
  uint8_t leds_ = 0;
  uint16_t prev_stop2_seen_ = 0;
  bool prev_stop2_known_ = false;  ///< a baseline of the previous STOP2 counter
  bool stop_latched_ = false;
  /// Modbus watchdog: armed by the first request, so a station configured
  /// without a PC is not stopped; a silent PC then latches a stop.
  bool watchdog_armed_ = false;
  uint16_t requests_seen_ = 0;
  uint32_t last_request_us_ = 0;
};

}  // namespace gateway
}  // namespace mb2co
