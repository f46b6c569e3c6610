#include "gateway/line_app.h"

namespace mb2co {
namespace gateway {

// Entries are reached as members of the value block, named after index and
// sub-index (MB2CO_OD_MEMBER): v_->v_0x2100_2 is 2100h/2. They are written as
// ObjectDictionary::set() would (no hooks run there either); put() for the
// PDO-mappable ones, whose changes the TPDOs must see.

void LineApp::init(canopen::ObjectDictionary* od, od::GatewayValues* values) {
  od_ = od;
  v_ = values;
}

void LineApp::neighbour_config(uint8_t id, uint8_t* prev, uint8_t* next) const {
  const bool ring = v_->v_0x2000_3 != 0;
  const uint8_t n = v_->v_0x2000_4;
  *prev = id > 1 ? static_cast<uint8_t>(id - 1) : (ring ? n : 0);
  *next = id < n ? static_cast<uint8_t>(id + 1) : (ring ? 1 : 0);
  if (*prev == id) *prev = 0;  // a "line" of one station
  if (*next == id) *next = 0;
}

namespace {

// COB-ID of an RPDO receiving node `id`'s PDO at base + id; not valid (bit
// 31) with that base when there is no such node. Out of line: three call
// sites (-12 B on the Uno).
__attribute__((noinline)) uint32_t rpdo_cob_id(uint16_t base, uint8_t id) {
  return id != 0 ? static_cast<uint32_t>(base + id) : 0x80000000u | base;
}

// A 1016h entry watching node `id` (0: none) with `time_ms` (0: off).
uint32_t consumer_entry(uint8_t id, uint16_t time_ms) {
  return id != 0 && time_ms != 0 ? (static_cast<uint32_t>(id) << 16) | time_ms : 0;
}

}  // namespace

void LineApp::on_reset(uint8_t node_id) {
  od::GatewayValues& v = *v_;
  uint8_t prev = 0;
  uint8_t next = 0;
  neighbour_config(node_id, &prev, &next);
  v.v_0x2110_4 = prev;
  v.v_0x2120_4 = next;
  v.v_0x2110_3 = prev ? kNeighbourUnknown : kNeighbourNone;
  v.v_0x2120_3 = next ? kNeighbourUnknown : kNeighbourNone;
  prev_stop2_known_ = false;
  if (v.v_0x2000_7 != 0) return;  // PDOs and 1016h as stored
  // Derived: subscribe to the neighbours' TPDO1 (line state) and to the
  // watched station's TPDO2 (buttons), watch both neighbours' heartbeats.
  v.v_0x1400_1 = rpdo_cob_id(0x180, prev);
  v.v_0x1401_1 = rpdo_cob_id(0x180, next);
  uint8_t watched = v.v_0x2130_2;
  if (watched == 0) watched = prev;
  v.v_0x1402_1 = rpdo_cob_id(0x280, watched);
  // 3 x 1017h, at most the 65535 ms of a 1016h entry: a 32-bit product OR-ed
  // in whole turned the node id into another (90000 ms made id 4 into id 5).
  const uint16_t hb_ms = v.v_0x1017_0;
  const uint16_t consumer_ms = hb_ms > 0xFFFFu / 3u ? 0xFFFFu : static_cast<uint16_t>(3u * hb_ms);
  v.v_0x1016_1 = consumer_entry(prev, consumer_ms);
  v.v_0x1016_2 = consumer_entry(next != prev ? next : 0, consumer_ms);
}

void LineApp::on_heartbeat(uint8_t node_id, canopen::HbEvent event) {
  const bool alive = event == canopen::kHbStarted || event == canopen::kHbStateChanged;
  const uint8_t status = alive ? kNeighbourAlive : kNeighbourUnknown;
  if (node_id == v_->v_0x2110_4) {
    v_->v_0x2110_3 = status;
    if (!alive) prev_stop2_known_ = false;  // its counter restarts or is stale
  }
  if (node_id == v_->v_0x2120_4) v_->v_0x2120_3 = status;
}

void LineApp::latch_stop(StopCause cause) {
  stop_latched_ = true;
  v_->v_0x2100_4 = cause;
}

void LineApp::on_rpdo(uint8_t n, uint32_t now_us) {
  if (n == 0) {
    // A changed STOP2 counter of the previous station: new STOP2 events. The
    // first value heard is only a baseline.
    const uint16_t count = v_->v_0x2110_2;
    if (prev_stop2_known_ && count != prev_stop2_seen_) latch_stop(kCauseStop2Previous);
    prev_stop2_seen_ = count;
    prev_stop2_known_ = true;
  } else if (n == 2) {
    v_->v_0x2300_3 = now_us;
  }
}

uint32_t LineApp::on_run_command(uint8_t value) {
  if (value == 0) stop_latched_ = false;  // the PC has seen the stop
  return canopen::kSdoOk;
}

namespace {

// LED of a neighbour: its RUN state while alive, `blink` while unknown.
bool led_for(uint8_t status, uint8_t run, bool blink) {
  return status == kNeighbourAlive ? run != 0 : status == kNeighbourUnknown && blink;
}

}  // namespace

uint8_t LineApp::process(uint32_t now_us, uint8_t raw, uint8_t nmt_state, uint16_t modbus_requests) {
  od::GatewayValues& v = *v_;
  if (modbus_requests != requests_seen_) {
    requests_seen_ = modbus_requests;
    last_request_us_ = now_us;
    watchdog_armed_ = true;
  }
  const uint32_t watchdog_us = static_cast<uint32_t>(v.v_0x2000_9) * 1000u;
  if (watchdog_armed_ && watchdog_us != 0 && now_us - last_request_us_ > watchdog_us) {
    watchdog_armed_ = false;  // one stop per silence; the next request re-arms
    latch_stop(kCausePcSilent);
  }
  const uint32_t debounce_us = static_cast<uint32_t>(v.v_0x2000_6) * 1000u;
  // The bit walks by a shift of one: a shift by a variable count is a loop
  // on the AVR (-14 B on the Uno).
  for (uint8_t i = 0, bit = 1; i < 3; ++i, bit = static_cast<uint8_t>(bit << 1)) {
    if ((raw ^ raw_) & bit) raw_since_us_[i] = now_us;
    if (!((raw ^ stable_) & bit) || now_us - raw_since_us_[i] < debounce_us) continue;
    stable_ ^= bit;
    v.v_0x2300_1 = raw_since_us_[i];  // when the contact really moved
    if (!(stable_ & bit)) continue;   // a release: nothing else to do
    if (bit == kStart) ++v.v_0x2100_5;
    if (bit == kStop) {
      ++v.v_0x2100_6;
      latch_stop(kCauseStopButton);
    }
    if (bit == kStop2) {
      put(v.v_0x2100_3, v.v_0x2100_3 + 1u);
      latch_stop(kCauseStop2Here);
    }
  }
  raw_ = raw;
  put(v.v_0x6000_1, stable_);
  put(v.v_0x2140_1, stable_ & 1u);
  put(v.v_0x2140_2, (stable_ >> 1) & 1u);
  put(v.v_0x2140_3, (stable_ >> 2) & 1u);

  const bool run = v.v_0x2100_1 != 0 && !stop_latched_;
  if (run) v.v_0x2100_4 = kCauseNone;
  put(v.v_0x2100_2, run ? 1u : 0u);

  uint8_t leds = run ? kLedRunSelf : 0;
  const bool blink = ((now_us / kBlinkHalfPeriodUs) & 1u) != 0;
  if (led_for(v.v_0x2110_3, v.v_0x2110_1, blink)) leds |= kLedRunPrev;
  if (led_for(v.v_0x2120_3, v.v_0x2120_1, blink)) leds |= kLedRunNext;
  if (v.v_0x6200_1 & 1u) leds |= kLedLab;
  if ((leds ^ leds_) & kLedLab) v.v_0x2300_2 = now_us;
  leds_ = leds;
  put(v.v_0x2200_0, leds);
  v.v_0x2002_0 = nmt_state;
  return leds;
}

}  // namespace gateway
}  // namespace mb2co
