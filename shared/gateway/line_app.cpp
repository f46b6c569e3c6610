#include "gateway/line_app.h"

namespace mb2co {
namespace gateway {

using canopen::ObjectDictionary;

void LineApp::init(ObjectDictionary* od) {
  od_ = od;
  r_run_cmd_ = row(0x2100, 1);
  r_run_ = row(0x2100, 2);
  r_stop2_count_ = row(0x2100, 3);
  r_cause_ = row(0x2100, 4);
  r_start_count_ = row(0x2100, 5);
  r_stop_count_ = row(0x2100, 6);
  r_prev_run_ = row(0x2110, 1);
  r_prev_stop2_ = row(0x2110, 2);
  r_prev_status_ = row(0x2110, 3);
  r_prev_id_ = row(0x2110, 4);
  r_next_run_ = row(0x2120, 1);
  r_next_status_ = row(0x2120, 3);
  r_next_id_ = row(0x2120, 4);
  r_inputs_ = row(0x6000, 1);
  r_buttons_ = row(0x2140, 1);
  r_leds_ = row(0x2200, 0);
  r_outputs_ = row(0x6200, 1);
  r_nmt_ = row(0x2002, 0);
  r_edge_us_ = row(0x2300, 1);
  r_led_us_ = row(0x2300, 2);
  r_remote_us_ = row(0x2300, 3);
  r_debounce_ = row(0x2000, 6);
  r_watchdog_ = row(0x2000, 9);
}

void LineApp::neighbour_config(uint8_t id, uint8_t* prev, uint8_t* next) const {
  const bool ring = od_->get(row(0x2000, 3)) != 0;
  const uint8_t n = static_cast<uint8_t>(od_->get(row(0x2000, 4)));
  *prev = id > 1 ? static_cast<uint8_t>(id - 1) : (ring ? n : 0);
  *next = id < n ? static_cast<uint8_t>(id + 1) : (ring ? 1 : 0);
  if (*prev == id) *prev = 0;  // a "line" of one station
  if (*next == id) *next = 0;
}

void LineApp::on_reset(uint8_t node_id) {
  uint8_t prev = 0;
  uint8_t next = 0;
  neighbour_config(node_id, &prev, &next);
  od_->set(r_prev_id_, prev);
  od_->set(r_next_id_, next);
  od_->set(r_prev_status_, prev ? kNeighbourUnknown : kNeighbourNone);
  od_->set(r_next_status_, next ? kNeighbourUnknown : kNeighbourNone);
  prev_stop2_known_ = false;
  if (od_->get(row(0x2000, 7)) != 0) return;  // PDOs and 1016h as stored
  // Derived: subscribe to the neighbours' TPDO1 (line state) and to the
  // watched station's TPDO2 (buttons), watch both neighbours' heartbeats.
  const uint32_t off = 0x80000000u;
  od_->set(row(0x1400, 1), prev ? 0x180u + prev : off | 0x180u);
  od_->set(row(0x1401, 1), next ? 0x180u + next : off | 0x180u);
  uint8_t watched = static_cast<uint8_t>(od_->get(row(0x2130, 2)));
  if (watched == 0) watched = prev;
  od_->set(row(0x1402, 1), watched ? 0x280u + watched : off | 0x280u);
  const uint32_t consumer_ms = 3u * od_->get(row(0x1017, 0));
  od_->set(row(0x1016, 1), prev && consumer_ms ? (static_cast<uint32_t>(prev) << 16) | consumer_ms : 0);
  od_->set(row(0x1016, 2),
           next && next != prev && consumer_ms ? (static_cast<uint32_t>(next) << 16) | consumer_ms : 0);
}

void LineApp::on_heartbeat(uint8_t node_id, canopen::HbEvent event) {
  const bool alive = event == canopen::kHbStarted || event == canopen::kHbStateChanged;
  const uint8_t status = alive ? kNeighbourAlive : kNeighbourUnknown;
  if (node_id == od_->get(r_prev_id_)) {
    od_->set(r_prev_status_, status);
    if (!alive) prev_stop2_known_ = false;  // its counter restarts or is stale
  }
  if (node_id == od_->get(r_next_id_)) od_->set(r_next_status_, status);
}

void LineApp::latch_stop(StopCause cause) {
  stop_latched_ = true;
  od_->set(r_cause_, cause);
}

void LineApp::on_rpdo(uint8_t n, uint32_t now_us) {
  if (n == 0) {
    // A changed STOP2 counter of the previous station: new STOP2 events. The
    // first value heard is only a baseline.
    const uint16_t count = static_cast<uint16_t>(od_->get(r_prev_stop2_));
    if (prev_stop2_known_ && count != prev_stop2_seen_) latch_stop(kCauseStop2Previous);
    prev_stop2_seen_ = count;
    prev_stop2_known_ = true;
  } else if (n == 2) {
    od_->set(r_remote_us_, now_us);
  }
}

uint32_t LineApp::on_run_command(uint8_t value) {
  if (value == 0) stop_latched_ = false;  // the PC has seen the stop
  return canopen::kSdoOk;
}

bool LineApp::led_for(uint16_t status_row, uint16_t run_row, uint32_t now_us) const {
  switch (od_->get(status_row)) {
    case kNeighbourAlive:
      return od_->get(run_row) != 0;
    case kNeighbourUnknown:
      return ((now_us / kBlinkHalfPeriodUs) & 1u) != 0;
    default:
      return false;
  }
}

static void count_up(ObjectDictionary* od, uint16_t row) {
  od->set(row, static_cast<uint16_t>(od->get(row) + 1u));
}

uint8_t LineApp::process(uint32_t now_us, uint8_t raw, uint8_t nmt_state, uint16_t modbus_requests) {
  if (modbus_requests != requests_seen_) {
    requests_seen_ = modbus_requests;
    last_request_us_ = now_us;
    watchdog_armed_ = true;
  }
  const uint32_t watchdog_us = od_->get(r_watchdog_) * 1000u;
  if (watchdog_armed_ && watchdog_us != 0 && now_us - last_request_us_ > watchdog_us) {
    watchdog_armed_ = false;  // one stop per silence; the next request re-arms
    latch_stop(kCausePcSilent);
  }
  const uint32_t debounce_us = od_->get(r_debounce_) * 1000u;
  for (uint8_t i = 0; i < 3; ++i) {
    const uint8_t bit = static_cast<uint8_t>(1u << i);
    if ((raw ^ raw_) & bit) raw_since_us_[i] = now_us;
    if (!((raw ^ stable_) & bit) || now_us - raw_since_us_[i] < debounce_us) continue;
    stable_ ^= bit;
    od_->set(r_edge_us_, raw_since_us_[i]);  // when the contact really moved
    if (!(stable_ & bit)) continue;           // a release: nothing else to do
    if (bit == kStart) count_up(od_, r_start_count_);
    if (bit == kStop) {
      count_up(od_, r_stop_count_);
      latch_stop(kCauseStopButton);
    }
    if (bit == kStop2) {
      count_up(od_, r_stop2_count_);
      latch_stop(kCauseStop2Here);
    }
  }
  raw_ = raw;
  od_->set(r_inputs_, stable_);
  for (uint8_t i = 0; i < 3; ++i) od_->set(static_cast<uint16_t>(r_buttons_ + i), (stable_ >> i) & 1u);

  const bool run = od_->get(r_run_cmd_) != 0 && !stop_latched_;
  if (run) od_->set(r_cause_, kCauseNone);
  od_->set(r_run_, run ? 1u : 0u);

  uint8_t leds = run ? kLedRunSelf : 0;
  if (led_for(r_prev_status_, r_prev_run_, now_us)) leds |= kLedRunPrev;
  if (led_for(r_next_status_, r_next_run_, now_us)) leds |= kLedRunNext;
  if (od_->get(r_outputs_) & 1u) leds |= kLedLab;
  if ((leds ^ leds_) & kLedLab) od_->set(r_led_us_, now_us);
  leds_ = leds;
  od_->set(r_leds_, leds);
  od_->set(r_nmt_, nmt_state);
  return leds;
}

}  // namespace gateway
}  // namespace mb2co
