#include "canopen/time_stamp.h"

#include <string.h>

// Nothing where the profile has no TIME (the file's mere code in the link
// moves the Uno image's layout).
#if MB2CO_CONFIG_TIME

#include "canopen/frame_out.h"
#include "canopen/pdo_map.h"

namespace mb2co {
namespace canopen {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "OD values are stored little-endian: loaded in place");

uint32_t TimeStamp::load(const uint8_t* p) {
  uint32_t v;
  memcpy(&v, p, sizeof v);
  return v;
}

void TimeStamp::store(uint8_t* p, uint32_t v) {
  memcpy(p, &v, sizeof v);
}

void TimeStamp::init(ObjectDictionary* od, uint32_t now_us) {
  // 1013h's value follows 1012h's in the value block (both or neither:
  // MB2CO_WITH_TIME, two UNSIGNED32 members in a row).
  cob_ = od->ram_untracked(od->find(0x1012, 0));
  at_us_ = now_us;
  set_ = false;
#if MB2CO_CONFIG_TIME >= 2
  producing_ = false;
#endif
}

uint32_t TimeStamp::offset_us() const {
  return stamp() - at_us_;
}

void TimeStamp::refresh(uint32_t now_us) {
  set_stamp(stamp() + (now_us - at_us_));
  at_us_ = now_us;
}

bool TimeStamp::on_frame(const CanFrame& f, uint32_t now_us, bool allowed) {
  const uint32_t cob_id = cob();
  if (!(cob_id & kTimeConsumer) || f.id != (cob_id & 0x7FFu) || f.rtr()) return false;
  // Taken (not handed on to other services) whether or not it sets the
  // clock: no other service of this node has this id.
  if (!allowed || f.dlc != kTimeFrameLength) return true;
  const TimeOfDay t = decode_time_of_day(f.data);
  set_stamp(network_us_of(t));
  at_us_ = now_us;
  set_at_us_ = stamp();
  set_ = true;
#if MB2CO_CONFIG_TIME >= 2
  day_ = t;
  day_base_us_ = network_us_of(t);
#endif
  return true;
}

SdoAbort TimeStamp::on_write(uint16_t index, const uint8_t* data, bool apply) {
  const uint32_t v = le32(data);
  if (index == 0x1013) {
    // The OD stores the value: the network time at the instant of the
    // request (refresh() ran at its arrival, at_us_).
    if (!apply) return kSdoOk;
    set_ = true;
    set_at_us_ = v;
#if MB2CO_CONFIG_TIME >= 2
    // 1013h cannot say the day (mod 2^32): the producer's TIME_OF_DAY runs on
    // unchanged, its base moves with the µs clock.
    day_base_us_ += v - stamp();
#else
    (void)v;
#endif
    return kSdoOk;
  }
  // 1012h.
  if (v & 0x20000000u) return kAbortInvalidValue;                                 // 29-bit ids: not supported
  if (can_id_restricted(v & 0x7FFu)) return kAbortInvalidValue;                   // CiA 301 §7.3.5
  if (!profile::kTimeProducer && (v & kTimeProducer)) return kAbortInvalidValue;  // cannot produce
  return kSdoOk;
}

#if MB2CO_CONFIG_TIME >= 2

namespace {

TimeOfDay advance(TimeOfDay t, uint32_t ms) {
  // ms < 2^32 / 1000 (71 minutes): at most one midnight.
  t.ms += ms;
  if (t.ms >= kMsPerDay) {
    t.ms -= kMsPerDay;
    ++t.days;
  }
  return t;
}

}  // namespace

TimeOfDay TimeStamp::time_of_day(uint32_t now_us) const {
  return advance(day_, (network_us(now_us) - day_base_us_) / 1000u);
}

void TimeStamp::set_time_of_day(const TimeOfDay& t, uint32_t now_us) {
  refresh(now_us);
  day_ = t;
  day_base_us_ = network_us_of(t);
  set_stamp(day_base_us_);
  set_at_us_ = day_base_us_;
  set_ = true;
}

void TimeStamp::process(uint32_t now_us, bool allowed, const CanSink& sink) {
  refresh(now_us);
  if (!allowed || !(cob() & kTimeProducer)) {
    producing_ = false;
    return;
  }
  const uint32_t period_us = 1000u * (period_ms_ != 0 ? period_ms_ : kDefaultProducerPeriodMs);
  if (producing_ && now_us - sent_us_ < period_us) return;
  producing_ = true;
  sent_us_ = now_us;
  // The day moves on with what is sent (the sub-ms rest stays in the base),
  // so time_of_day() never counts over more than one period.
  const uint32_t ms = (network_us(now_us) - day_base_us_) / 1000u;
  day_ = advance(day_, ms);
  day_base_us_ += ms * 1000u;
  uint8_t data[kTimeFrameLength];
  encode_time_of_day(day_, data);
  send_frame(sink, can_id(), kTimeFrameLength, data);
}

void TimeStamp::next_deadline(NextDeadline& d, bool allowed) const {
  if (!allowed || !(cob() & kTimeProducer)) {
    if (producing_) d.now();
    return;
  }
  if (!producing_) return d.now();
  d.at(sent_us_ + 1000u * (period_ms_ != 0 ? period_ms_ : kDefaultProducerPeriodMs));
}

#else

void TimeStamp::process(uint32_t now_us, bool, const CanSink&) {
  refresh(now_us);
}

void TimeStamp::next_deadline(NextDeadline&, bool) const {}

#endif

}  // namespace canopen
}  // namespace mb2co
#endif
