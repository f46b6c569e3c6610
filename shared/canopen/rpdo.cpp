#include "canopen/rpdo.h"

#include <string.h>

#include "canopen/clock.h"
#include "canopen/pdo_map.h"

namespace mb2co {
namespace canopen {

// Row offsets inside one communication record (sub 4 is absent).
enum : uint8_t { kCob = 1, kType = 2, kEvent = 4 };

uint32_t Rpdos::comm(uint8_t n, uint8_t k) const {
  return od_->get(static_cast<uint16_t>(comm_row(n) + k));
}

void Rpdos::init(ObjectDictionary* od, EmcyProducer* emcy) {
  od_ = od;
  emcy_ = emcy;
  pdo_find_records(*od, 0x1400, &rec_);
  memset(st_, 0, sizeof st_);
}

void Rpdos::apply(uint8_t n, const uint8_t* data) {
  pdo_apply(*od_, map_row(n), data);
  if (cb_ != nullptr) cb_(cb_ctx_, n);
}

// One EMCY per kind of length error while any RPDO shows it; cleared when
// every RPDO has received a frame of the right length again.
void Rpdos::update_length_errors() {
  bool any_short = false;
  bool any_long = false;
  for (const State& s : st_) {
    any_short = any_short || (s.flags & kShort);
    any_long = any_long || (s.flags & kLong);
  }
  emcy_->report(kEmcyPdoLength, any_short, kErrCommunication);
  emcy_->report(kEmcyPdoLengthExceeded, any_long, kErrCommunication);
}

bool Rpdos::on_frame(const CanFrame& f, uint32_t now_us) {
  if (f.extended()) return false;
  // Every valid RPDO on this COB-ID gets the frame: several RPDOs may
  // subscribe to one producer and map its data differently.
  bool matched = false;
  for (uint8_t n = 0; n < kPdoCount; ++n) {
    const uint32_t cob = comm(n, kCob);
    if ((cob & 0x80000000u) || (cob & 0x7FFu) != f.id) continue;
    matched = true;
    if (f.rtr()) continue;  // nothing to answer for a receive PDO
    // Nothing mapped: the PDO carries nothing for us (as a TPDO with no
    // mapping is not sent), so no length check and no EMCY either.
    if (od_->get(map_row(n)) == 0) continue;
    State& s = st_[n];
    const uint8_t need = pdo_mapped_bytes(*od_, map_row(n));
    s.flags = static_cast<uint8_t>(s.flags & ~(kShort | kLong));
    if (f.dlc < need) {
      s.flags |= kShort;
    } else if (f.dlc > need) {
      s.flags |= kLong;
    }
    update_length_errors();
    if (s.flags & kShort) continue;  // not processed
    const uint16_t event_ms = static_cast<uint16_t>(comm(n, kEvent));
    if (event_ms != 0) {
      s.flags |= kMonitoring;
      // 32-bit product: an AVR's int is 16 bits.
      s.deadline_us = now_us + static_cast<uint32_t>(event_ms) * 1000u;
    }
    if (s.flags & kTimedOut) {
      s.flags = static_cast<uint8_t>(s.flags & ~kTimedOut);
      bool others = false;
      for (const State& o : st_) others = others || (o.flags & kTimedOut);
      if (!others) emcy_->clear(kEmcyRpdoTimeout);
    }
    const uint8_t type = static_cast<uint8_t>(comm(n, kType));
    if (type <= 240) {
      memcpy(s.buffer, f.data, 8);
      s.flags |= kBuffered;
    } else {
      apply(n, f.data);
    }
  }
  return matched;
}

void Rpdos::on_sync() {
  for (uint8_t n = 0; n < kPdoCount; ++n) {
    if (!(st_[n].flags & kBuffered)) continue;
    st_[n].flags = static_cast<uint8_t>(st_[n].flags & ~kBuffered);
    apply(n, st_[n].buffer);
  }
}

void Rpdos::process(uint32_t now_us) {
  for (State& s : st_) {
    if ((s.flags & kMonitoring) && !(s.flags & kTimedOut) && time_reached(now_us, s.deadline_us)) {
      s.flags |= kTimedOut;
      emcy_->raise(kEmcyRpdoTimeout, kErrCommunication);
    }
  }
}

void Rpdos::next_deadline(NextDeadline& d) const {
  for (const State& s : st_) {
    if ((s.flags & kMonitoring) && !(s.flags & kTimedOut)) d.at(s.deadline_us);
  }
}

void Rpdos::stop() {
  for (State& s : st_) s.flags = static_cast<uint8_t>(s.flags & (kTimedOut | kShort | kLong));
}

SdoAbort Rpdos::on_write(uint16_t index, uint8_t sub, const uint8_t* data, bool apply) {
  if (index >= 0x1600) {  // mapping
    const uint8_t n = static_cast<uint8_t>(index - 0x1600);
    return pdo_check_map_write(*od_, comm(n, kCob), map_row(n), rec_.map_stride, sub, data, true);
  }
  const uint8_t n = static_cast<uint8_t>(index - 0x1400);
  const uint32_t cur = comm(n, kCob);
  switch (sub) {
    case 1: {
      const uint32_t v = le32(data);
      const SdoAbort abort = pdo_check_cob_id(cur, v);
      if (apply && abort == kSdoOk && (v & 0x80000000u)) st_[n].flags = 0;  // disabled: forget state
      return abort;
    }
    case 2:
      if (data[0] > 240 && data[0] < 254) return kAbortInvalidValue;
      return kSdoOk;
    case 3:
    case 5:
      return kSdoOk;
    default:
      return kAbortNoSubindex;
  }
}

}  // namespace canopen
}  // namespace mb2co
