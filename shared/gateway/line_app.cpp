#include "gateway/line_app.h"

namespace mb2co {
namespace gateway {

// Entries are reached as members of the value block, named by the OD list's
// identifier column: v_->x2100_2_runState is 2100h/2. They are written as
// ObjectDictionary::set() would (no hooks run there either). The
// PDO-mappable ones (PdoMapped) can only be stored by ObjectDictionary::put(),
// which lets the TPDOs see the change.

void LineApp::init(canopen::ObjectDictionary* od, od::GatewayValues* values) {
  od_ = od;
  v_ = values;
}

void LineApp::neighbour_config(uint8_t id, uint8_t* prev, uint8_t* next) const {
  const bool ring = v_->x2000_3_topology != 0;
  const uint8_t n = v_->x2000_4_stationCount;
  *prev = id > 1 ? static_cast<uint8_t>(id - 1) : (ring ? n : 0);
  *next = id < n ? static_cast<uint8_t>(id + 1) : (ring ? 1 : 0);
  if (*prev == id) *prev = 0;  // a "line" of one station
  if (*next == id) *next = 0;
}

namespace {

// COB-ID of an RPDO receiving node `id`'s PDO at base + id; not valid (bit
// 31) with that base when there is no such node. Out of line: three call
// sites.
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
  v.x2110_4_prevNodeId = prev;
  v.x2120_4_nextNodeId = next;
  // Until their TPDO1 comes, the neighbours' RUN states and counters are
  // the defaults just restored, not values they sent.
  v.x2110_3_prevStatus = prev ? kNeighbourUnknown | kNeighbourNotHeard : kNeighbourNone;
  v.x2120_3_nextStatus = next ? kNeighbourUnknown | kNeighbourNotHeard : kNeighbourNone;
  prev_stop2_known_ = false;
  if (v.x2000_7_pdoConfigAsStored != 0) return;  // PDOs and 1016h as stored
  // Derived: subscribe to the neighbours' TPDO1 (line state) and to the
  // watched station's TPDO2 (buttons), watch both neighbours' heartbeats.
  v.x1400_1_cobId = rpdo_cob_id(0x180, prev);
  v.x1401_1_cobId = rpdo_cob_id(0x180, next);
  uint8_t watched = v.x2130_2_watchedNodeId;
  if (watched == 0) watched = prev;
  v.x1402_1_cobId = rpdo_cob_id(0x280, watched);
  // 3 x 1017h, at most the 65535 ms of a 1016h entry: a 32-bit product OR-ed
  // in whole turned the node id into another (90000 ms made id 4 into id 5).
  const uint16_t hb_ms = v.x1017_0_producerHeartbeatTime;
  const uint16_t consumer_ms = hb_ms > 0xFFFFu / 3u ? 0xFFFFu : static_cast<uint16_t>(3u * hb_ms);
  v.x1016_1_consumerHeartbeatTime1 = consumer_entry(prev, consumer_ms);
  v.x1016_2_consumerHeartbeatTime2 = consumer_entry(next != prev ? next : 0, consumer_ms);
}

void LineApp::on_heartbeat(uint8_t node_id, canopen::HbEvent event) {
  const bool alive = event == canopen::kHbStarted || event == canopen::kHbStateChanged;
  static_assert(kNeighbourUnknown == 0 && kNeighbourAlive == 1, "the status is `alive`");
  // The kNeighbourNotHeard flag stays: a heartbeat is not a TPDO1.
  if (node_id == v_->x2110_4_prevNodeId) {
    v_->x2110_3_prevStatus = static_cast<uint8_t>((v_->x2110_3_prevStatus & kNeighbourNotHeard) | alive);
    if (!alive) prev_stop2_known_ = false;  // its counter restarts or is stale
  }
  if (node_id == v_->x2120_4_nextNodeId)
    v_->x2120_3_nextStatus = static_cast<uint8_t>((v_->x2120_3_nextStatus & kNeighbourNotHeard) | alive);
}

void LineApp::latch_stop(StopCause cause) {
  stop_latched_ = true;
  v_->x2100_4_stopCause = cause;
}

void LineApp::on_rpdo(uint8_t n, uint32_t now_us) {
  // RPDO1 and RPDO2 carry the previous and next station's TPDO1: heard now.
  if (n < 2) {
    uint8_t& status = n == 0 ? v_->x2110_3_prevStatus : v_->x2120_3_nextStatus;
    status &= static_cast<uint8_t>(~kNeighbourNotHeard);
  }
  if (n == 0) {
    // A changed STOP2 counter of the previous station: new STOP2 events. The
    // first value heard is only a baseline.
    const uint16_t count = v_->x2110_2_prevStop2Count;
    if (prev_stop2_known_ && count != prev_stop2_seen_) latch_stop(kCauseStop2Previous);
    prev_stop2_seen_ = count;
    prev_stop2_known_ = true;
  } else if (n == 2) {
    v_->x2300_3_remoteButtonsUs = stamp(now_us);
  }
}

namespace {

// LED of a neighbour: its RUN state while alive and heard, `blink` while unknown.
bool led_for(uint8_t status, uint8_t run, bool blink) {
  return status == kNeighbourAlive ? run != 0 : neighbour_shown_unknown(status) && blink;
}

// The LED bits to drive at `now_us` with RUN state `run`. Inlined into
// process() as before (a call costs the Uno's flash); next_deadline() asks too.
__attribute__((always_inline)) inline uint8_t leds_at(const od::GatewayValues& v, uint32_t now_us, bool run) {
  uint8_t leds = run ? kLedRunSelf : 0;
  const bool blink = ((now_us / LineApp::kBlinkHalfPeriodUs) & 1u) != 0;
  if (led_for(v.x2110_3_prevStatus, v.x2110_1_prevRunState, blink)) leds |= kLedRunPrev;
  if (led_for(v.x2120_3_nextStatus, v.x2120_1_nextRunState, blink)) leds |= kLedRunNext;
  if (v.x6200_1_writeOutput8Bit1 & 1u) leds |= kLedLab;
  return leds;
}

}  // namespace

uint8_t LineApp::process(uint32_t now_us, uint8_t raw, uint8_t nmt_state, uint16_t modbus_requests) {
  od::GatewayValues& v = *v_;
  if (modbus_requests != requests_seen_) {
    requests_seen_ = modbus_requests;
    last_request_us_ = now_us;
    watchdog_armed_ = true;
  }
  const uint32_t watchdog_us = static_cast<uint32_t>(v.x2000_9_modbusWatchdogMs) * 1000u;
  if (watchdog_armed_ && watchdog_us != 0 && now_us - last_request_us_ > watchdog_us) {
    watchdog_armed_ = false;  // one stop per silence; the next request re-arms
    latch_stop(kCausePcSilent);
  }
  const uint32_t debounce_us = static_cast<uint32_t>(v.x2000_6_debounceMs) * 1000u;
  // The bit walks by a shift of one: a shift by a variable count is a loop
  // on the AVR.
  for (uint8_t i = 0, bit = 1; i < 3; ++i, bit = static_cast<uint8_t>(bit << 1)) {
    if ((raw ^ raw_) & bit) raw_since_us_[i] = now_us;
    if (!((raw ^ stable_) & bit) || now_us - raw_since_us_[i] < debounce_us) continue;
    stable_ ^= bit;
    v.x2300_1_buttonEdgeUs = stamp(raw_since_us_[i]);  // when the contact really moved
    if (!(stable_ & bit)) continue;                    // a release: nothing else to do
    if (bit == kStart) ++v.x2100_5_startCount;
    if (bit == kStop) {
      ++v.x2100_6_stopCount;
      latch_stop(kCauseStopButton);
    }
    if (bit == kStop2) {
      od_->put(v.x2100_3_stop2Count, v.x2100_3_stop2Count + 1u);
      latch_stop(kCauseStop2Here);
    }
  }
  raw_ = raw;
  od_->put(v.x6000_1_readInput8Bit1, stable_);
  od_->put(v.x2140_1_startPressed, stable_ & 1u);
  od_->put(v.x2140_2_stopPressed, (stable_ >> 1) & 1u);
  od_->put(v.x2140_3_stop2Pressed, (stable_ >> 2) & 1u);

  const bool run = v.x2100_1_runCommand != 0 && !stop_latched_;
  if (run) v.x2100_4_stopCause = kCauseNone;
  od_->put(v.x2100_2_runState, run ? 1u : 0u);

  const uint8_t leds = leds_at(v, now_us, run);
  if ((leds ^ leds_) & kLedLab) v.x2300_2_labLedUs = stamp(now_us);
  leds_ = leds;
  od_->put(v.x2200_0_leds, leds);
  v.x2002_0_nmtState = nmt_state;
  return leds;
}

void LineApp::next_deadline(NextDeadline& d, uint8_t nmt_state, uint16_t modbus_requests) const {
  const od::GatewayValues& v = *v_;
  const uint32_t now_us = d.now_us();
  // Everything process() stores is a function of its state and inputs; when
  // one of them changed since (the node's process() runs after this one in
  // a gateway pass, and its callbacks and resets write here), so does what
  // it would store now.
  const bool run = v.x2100_1_runCommand != 0 && !stop_latched_;  // as process() decides
  const uint8_t leds = leds_at(v, now_us, run);
  const bool stale = modbus_requests != requests_seen_ || nmt_state != v.x2002_0_nmtState || leds != leds_ ||
                     leds != v.x2200_0_leds || run != (v.x2100_2_runState != 0) ||
                     (run && v.x2100_4_stopCause != kCauseNone) || stable_ != v.x6000_1_readInput8Bit1 ||
                     (stable_ & 1u) != (v.x2140_1_startPressed ? 1u : 0u) ||
                     ((stable_ >> 1) & 1u) != (v.x2140_2_stopPressed ? 1u : 0u) ||
                     ((stable_ >> 2) & 1u) != (v.x2140_3_stop2Pressed ? 1u : 0u);
  if (stale) return d.now();
  const uint32_t watchdog_us = static_cast<uint32_t>(v.x2000_9_modbusWatchdogMs) * 1000u;
  // process() stops the station once the silence exceeds 2000h/9: 1 us later.
  if (watchdog_armed_ && watchdog_us != 0) d.at(last_request_us_ + watchdog_us + 1u);
  const uint32_t debounce_us = static_cast<uint32_t>(v.x2000_6_debounceMs) * 1000u;
  for (uint8_t i = 0, bit = 1; i < 3; ++i, bit = static_cast<uint8_t>(bit << 1)) {
    if ((raw_ ^ stable_) & bit) d.at(raw_since_us_[i] + debounce_us);
  }
  if (neighbour_shown_unknown(v.x2110_3_prevStatus) || neighbour_shown_unknown(v.x2120_3_nextStatus)) {
    // The next multiple of the half period; past the last one before the
    // clock wraps, the phase turns at the wrap (0).
    const uint32_t phase = now_us / kBlinkHalfPeriodUs + 1u;
    d.at(phase <= 0xFFFFFFFFu / kBlinkHalfPeriodUs ? phase * kBlinkHalfPeriodUs : 0u);
  }
}

}  // namespace gateway
}  // namespace mb2co
