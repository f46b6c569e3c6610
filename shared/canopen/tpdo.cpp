#include "canopen/tpdo.h"

#include <string.h>

#include "canopen/clock.h"
#include "canopen/frame_out.h"
#include "canopen/pdo_map.h"
#include "profiles/profile.h"

namespace mb2co {
namespace canopen {

// Row offsets inside one communication record (sub 4 is absent).
enum : uint8_t { kCob = 1, kType = 2, kInhibit = 3, kEvent = 4, kSyncStart = 5 };

uint32_t Tpdos::comm(uint8_t n, uint8_t k) const {
  return od_->get(static_cast<uint16_t>(comm_row(n) + k));
}

void Tpdos::init(ObjectDictionary* od) {
  od_ = od;
  pdo_find_records(*od, 0x1800, &rec_);
  memset(st_, 0, sizeof st_);
}

bool Tpdos::valid(uint8_t n, uint32_t* cob) const {
  *cob = comm(n, kCob);
  return !(*cob & 0x80000000u) && od_->get(map_row(n)) != 0;
}

void Tpdos::on_operational() {
  for (uint8_t n = 0; n < kPdoCount; ++n) {
    st_[n].flags = static_cast<uint8_t>(st_[n].flags & ~(kSent | kSyncStarted | kInhibiting));
    st_[n].sync_count = 0;
    const uint8_t type = static_cast<uint8_t>(comm(n, kType));
    if (type >= 254) st_[n].flags |= kPending;
  }
}

void Tpdos::request(uint8_t n) {
  if (n < kPdoCount) st_[n].flags |= kPending;
}

bool Tpdos::send(uint8_t n, uint32_t cob, const uint8_t* data, uint8_t len, const CanSink& sink,
                 uint32_t now_us) {
  if (!send_frame(sink, static_cast<uint16_t>(cob & 0x7FFu), len, data)) {
    ++send_failures_;
    return false;
  }
  State& s = st_[n];
  memcpy(s.last, data, 8);
  s.last_len = len;
  s.flags = static_cast<uint8_t>((s.flags & ~kPending) | kSent);
  const uint16_t inhibit = static_cast<uint16_t>(comm(n, kInhibit));
  if (inhibit != 0) {
    s.flags |= kInhibiting;
    // 32-bit product: an AVR's int is 16 bits (a 100 ms timer wrapped to 34.5 ms there).
    s.inhibit_until_us = now_us + static_cast<uint32_t>(inhibit) * 100u;
  }
  start_event_timer(n, now_us);
  return true;
}

void Tpdos::start_event_timer(uint8_t n, uint32_t now_us) {
  State& s = st_[n];
  const uint16_t event_ms = static_cast<uint16_t>(comm(n, kEvent));
  s.flags = static_cast<uint8_t>(s.flags & ~(kEventTimer | kEventWritten));
  if (event_ms != 0) {
    s.flags |= kEventTimer;
    s.event_deadline_us = now_us + static_cast<uint32_t>(event_ms) * 1000u;
  }
}

void Tpdos::build_and_send(uint8_t n, uint32_t cob, const CanSink& sink, uint32_t now_us) {
  uint8_t data[8];
  const uint8_t len = pdo_build(*od_, map_row(n), data);
  send(n, cob, data, len, sink, now_us);
}

Tpdos::SendNow Tpdos::send_now(uint8_t n, const CanSink& sink, uint32_t now_us) {
  uint32_t cob;
  if (n >= kPdoCount || !valid(n, &cob)) return kSendNowInvalid;
  const uint16_t failures = send_failures_;
  build_and_send(n, cob, sink, now_us);
  return send_failures_ == failures ? kSentNow : kSendNowRefused;
}

void Tpdos::process(uint32_t now_us, const CanSink& sink) {
  // While the OD is unchanged every payload is what it was at the previous
  // call, and so are validity and type (kEventType). A PDO whose last payload
  // went out then needs no rebuild unless a timer makes it due.
  const bool od_changed = od_->revision() != seen_revision_;
  seen_revision_ = od_->revision();
  for (uint8_t n = 0; n < kPdoCount; ++n) {
    State& s = st_[n];
    if (!od_changed && (s.flags & (kPending | kSent)) == kSent) {
      if (!(s.flags & kEventType)) continue;
      if ((s.flags & kEventTimer) && time_reached(now_us, s.event_deadline_us)) s.flags |= kPending;
      if ((s.flags & kInhibiting) && time_reached(now_us, s.inhibit_until_us)) {
        s.flags = static_cast<uint8_t>(s.flags & ~kInhibiting);
      }
      if (!(s.flags & kPending) || (s.flags & kInhibiting)) continue;
    }
    s.flags = static_cast<uint8_t>(s.flags & ~kEventType);
    // A written event time counts from its write (the write changed the
    // OD, so this full look follows it at once).
    if (s.flags & kEventWritten) start_event_timer(n, now_us);
    uint32_t cob = 0;
    if (!valid(n, &cob)) continue;
    const uint8_t type = static_cast<uint8_t>(comm(n, kType));
    uint8_t data[8];
    const uint8_t len = pdo_build(*od_, map_row(n), data);
    const bool changed = !(s.flags & kSent) || len != s.last_len || memcmp(data, s.last, len) != 0;
    if (type == 0) {  // acyclic synchronous: remember the change for the next SYNC
      if (changed) s.flags |= kPending;
      continue;
    }
    if (type < 254) continue;
    s.flags |= kEventType;
#if MB2CO_CONFIG_PROFILE_EVENTS
    if (changed && change_sends(n, type)) s.flags |= kPending;
#else
    if (changed) s.flags |= kPending;  // the station images: not a byte more
#endif
    if ((s.flags & kEventTimer) && time_reached(now_us, s.event_deadline_us)) s.flags |= kPending;
    if ((s.flags & kInhibiting) && time_reached(now_us, s.inhibit_until_us)) {
      s.flags = static_cast<uint8_t>(s.flags & ~kInhibiting);
    }
    if ((s.flags & kPending) && !(s.flags & kInhibiting)) send(n, cob, data, len, sink, now_us);
  }
}

void Tpdos::next_deadline(NextDeadline& d) const {
  if (od_->revision() != seen_revision_) return d.now();
  // The OD is as process() last saw it: kEventType is exact, and PDOs
  // without it (other types, not valid) only repeat what they did then.
  for (const State& s : st_) {
    if (!(s.flags & kEventType)) continue;
    const bool inhibiting = (s.flags & kInhibiting) && !time_reached(d.now_us(), s.inhibit_until_us);
    if ((s.flags & (kPending | kSent)) != kSent) {  // to send (a new one is pending)
      if (!inhibiting) return d.now();
      d.at(s.inhibit_until_us);
      continue;
    }
    if (s.flags & kEventTimer) d.at(s.event_deadline_us);
    // Ending the inhibit time is a change too: left to a later call, a
    // deadline 2^31 us old would read as ahead again.
    if (s.flags & kInhibiting) d.at(s.inhibit_until_us);
  }
}

// Type 252 samples at the SYNC only for the answer to a remote request.
#if MB2CO_CONFIG_TPDO_RTR
constexpr bool kAnswersRtr = true;
#else
constexpr bool kAnswersRtr = false;
#endif

void Tpdos::on_sync(uint8_t counter, const CanSink& sink, uint32_t now_us) {
  for (uint8_t n = 0; n < kPdoCount; ++n) {
    uint32_t cob = 0;
    if (!valid(n, &cob)) continue;
    State& s = st_[n];
    const uint8_t type = static_cast<uint8_t>(comm(n, kType));
    if (type == 0) {
      if (!(s.flags & kPending)) continue;
      build_and_send(n, cob, sink, now_us);
    } else if (type <= 240) {
      const uint8_t start = static_cast<uint8_t>(comm(n, kSyncStart));
      if (!(s.flags & kSyncStarted)) {
        if (start != 0 && counter != 0 && counter != start) continue;
        s.flags |= kSyncStarted;
        s.sync_count = static_cast<uint8_t>(type - 1);  // first transmission on this SYNC
      }
      if (++s.sync_count < type) continue;
      s.sync_count = 0;
      build_and_send(n, cob, sink, now_us);
    } else if (kAnswersRtr && type == 252) {  // sample now, send on request
      s.last_len = pdo_build(*od_, map_row(n), s.last);
      s.flags |= kSyncStarted;  // for 252: a sample is held
    }
  }
}

#if MB2CO_CONFIG_TPDO_RTR

bool Tpdos::on_rtr(const CanFrame& f, const CanSink& sink, uint32_t now_us) {
  for (uint8_t n = 0; n < kPdoCount; ++n) {
    uint32_t cob = 0;
    if (!valid(n, &cob) || (cob & 0x7FFu) != f.id) continue;
    if (cob & 0x40000000u) return true;  // RTR not allowed on this PDO: ignored
    const uint8_t type = static_cast<uint8_t>(comm(n, kType));
    if (type == 252 && (st_[n].flags & kSyncStarted)) {
      uint8_t data[8];
      memcpy(data, st_[n].last, 8);
      send(n, cob, data, st_[n].last_len, sink, now_us);
    } else {
      build_and_send(n, cob, sink, now_us);
    }
    return true;
  }
  return false;
}
#endif  // MB2CO_CONFIG_TPDO_RTR

SdoAbort Tpdos::on_write(uint16_t index, uint8_t sub, const uint8_t* data, bool apply) {
  if (index >= 0x1A00) {  // mapping
    const uint8_t n = static_cast<uint8_t>(index - 0x1A00);
    return pdo_check_map_write(*od_, comm(n, kCob), map_row(n), rec_.map_stride, sub, data, false);
  }
  const uint8_t n = static_cast<uint8_t>(index - 0x1800);
  const uint32_t cur = comm(n, kCob);
  const bool enabled = !(cur & 0x80000000u);
  switch (sub) {
    case 1: {
      const uint32_t v = le32(data);
      const SdoAbort abort = pdo_check_cob_id(cur, v);
      if (abort != kSdoOk) return abort;
      if (apply && !(v & 0x80000000u) && !enabled) {  // being enabled: start afresh
        st_[n].flags = kPending;
        st_[n].sync_count = 0;
      }
      return kSdoOk;
    }
    case 2:
      if (data[0] >= 241 && data[0] <= 251) return kAbortInvalidValue;
      if (apply) st_[n].flags = static_cast<uint8_t>(st_[n].flags & ~kSyncStarted);
      return kSdoOk;
    case 3:  // inhibit time: not changed while the PDO exists
    case 6:  // SYNC start value: likewise (rewriting the same value is no change)
      if (enabled && comm(n, sub == 3 ? kInhibit : kSyncStart) != (sub == 3 ? le16(data) : data[0])) {
        return kAbortInvalidValue;
      }
      if (sub == 6 && data[0] > 240) return kAbortInvalidValue;
      return kSdoOk;
    case 5:  // event timer: restarted with the new time (process(), the time of the write)
      if (apply) st_[n].flags |= kEventWritten;
      return kSdoOk;
    default:
      return kAbortNoSubindex;
  }
}

}  // namespace canopen
}  // namespace mb2co
