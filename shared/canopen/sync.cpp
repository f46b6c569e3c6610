#include "canopen/sync.h"

#include "canopen/frame_out.h"
#include "canopen/pdo_map.h"

namespace mb2co {
namespace canopen {

static const uint16_t kIndices[] MB2CO_FLASH = {0x1005, 0x1006, 0x1019};

void Sync::init(ObjectDictionary* od) {
  od_ = od;
  od->find_rows(kIndices, kRows, row_);
  counter_ = 0;
  restart_ = true;
}

Sync::Result Sync::on_frame(const CanFrame& f, uint8_t* counter) {
  if (f.rtr() || f.extended() || f.id != cob_id()) return kNotSync;
  const uint8_t overflow = static_cast<uint8_t>(od_->get(row_[k1019]));
  const uint8_t expected = overflow == 0 ? 0 : 1;
  if (f.dlc != expected) return kSyncLengthError;
  *counter = overflow == 0 ? 0 : f.data[0];
  return kSyncEvent;
}

void Sync::next_deadline(NextDeadline& d) const {
  const uint32_t cob = od_->get(row_[k1005]);
  const uint32_t period_us = od_->get(row_[k1006]);
  // Not producing: process() only re-arms the restart (already armed by the
  // write or reset that stopped it).
  if (!(cob & 0x40000000u) || period_us == 0) {
    if (!restart_) d.now();
    return;
  }
  if (restart_) return d.now();
  // Elapsed time, as process() counts it (1006h may exceed 2^31 us).
  const uint32_t elapsed_us = d.now_us() - period_start_us_;
  d.in(elapsed_us < period_us ? period_us - elapsed_us : 0);
}

bool Sync::process(uint32_t now_us, bool allowed, const CanSink& sink, uint8_t* counter) {
  const uint32_t cob = od_->get(row_[k1005]);
  const uint32_t period_us = od_->get(row_[k1006]);
  if (!(cob & 0x40000000u) || period_us == 0) {
    restart_ = true;
    return false;
  }
  if (restart_) {
    restart_ = false;
    counter_ = 0;
    period_start_us_ = now_us;
    return false;
  }
  // Elapsed time, not a deadline: 1006h may exceed 2^31 us, where a deadline
  // reads as passed to time_reached() (a SYNC on every call: a flood).
  if (now_us - period_start_us_ < period_us) return false;
  period_start_us_ += period_us;
  if (now_us - period_start_us_ >= period_us) period_start_us_ = now_us;  // no bursts
  if (!allowed) return false;
  const uint8_t overflow = static_cast<uint8_t>(od_->get(row_[k1019]));
  if (overflow != 0) counter_ = static_cast<uint8_t>(counter_ >= overflow ? 1 : counter_ + 1);
  send_frame(sink, static_cast<uint16_t>(cob & 0x7FFu), overflow != 0 ? 1 : 0, &counter_);
  *counter = overflow != 0 ? counter_ : 0;
  return true;
}

SdoAbort Sync::on_write(uint16_t index, const uint8_t* data, bool apply) {
  if (index == 0x1005) {
    const uint32_t v = le32(data);
    const uint32_t cur = od_->get(row_[k1005]);
    if (v & 0x20000000u) return kAbortInvalidValue;                // 29-bit ids not supported
    if (can_id_restricted(v & 0x7FFu)) return kAbortInvalidValue;  // CiA 301 §7.3.5
    // The CAN-ID may not change while this node produces SYNC.
    if ((cur & 0x40000000u) && (v & 0x40000000u) && (v & 0x7FFu) != (cur & 0x7FFu)) {
      return kAbortInvalidValue;
    }
    if (apply) restart_ = true;
  } else if (index == 0x1006) {
    if (apply) restart_ = true;
  } else if (index == 0x1019) {
    // CiA 301 §7.5.2.41: only while no communication cycle period is set.
    if (od_->get(row_[k1006]) != 0) return kAbortDeviceState;
    if (data[0] == 1) return kAbortInvalidValue;  // 0 or 2..240
    if (data[0] > 240) return kAbortValueTooHigh;
  }
  return kSdoOk;
}

}  // namespace canopen
}  // namespace mb2co
