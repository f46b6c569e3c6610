#include "canopen/emcy_producer.h"

#include <string.h>

#include "canopen/clock.h"
#include "canopen/frame_out.h"
#include "canopen/od_comm.h"
#include "canopen/pdo_map.h"

namespace mb2co {
namespace canopen {

static const uint16_t kIndices[] MB2CO_FLASH = {0x1001, 0x1003, 0x1014, 0x1015};

void EmcyProducer::init(ObjectDictionary* od) {
  od_ = od;
  od->find_rows(kIndices, kRows, row_);
  active_count_ = 0;
  queue_head_ = 0;
  queue_count_ = 0;
  inhibit_running_ = false;
  update_register();
}

bool EmcyProducer::active(uint16_t code) const {
  for (uint8_t i = 0; i < active_count_; ++i) {
    if (active_[i].code == code) return true;
  }
  return false;
}

void EmcyProducer::update_register() {
  uint8_t reg = 0;
  for (uint8_t i = 0; i < active_count_; ++i) reg = static_cast<uint8_t>(reg | active_[i].bits);
  if (active_count_ != 0) reg |= kErrGeneric;
  od_->set(row_[k1001], reg);
}

void EmcyProducer::push_history(uint16_t code, const uint8_t* info) {
  // Newest at sub 1 (CiA 301 §7.5.2.3); the manufacturer field's first two
  // bytes go into the upper half of the entry.
  uint32_t entry = code;
  if (info != nullptr)
    entry |= (static_cast<uint32_t>(info[0]) | (static_cast<uint32_t>(info[1]) << 8)) << 16;
  for (uint8_t s = kErrorHistoryLength; s > 1; --s) {
    od_->set(static_cast<uint16_t>(row_[k1003] + s), od_->get(static_cast<uint16_t>(row_[k1003] + s - 1)));
  }
  od_->set(static_cast<uint16_t>(row_[k1003] + 1), entry);
  const uint32_t n = od_->get(row_[k1003]);
  if (n < kErrorHistoryLength) od_->set(row_[k1003], n + 1);
}

void EmcyProducer::enqueue(uint16_t code, const uint8_t* info) {
  if (queue_count_ == kQueueLength) {
    ++overflows_;
    return;
  }
  Pending& p = queue_[(queue_head_ + queue_count_) % kQueueLength];
  put_le16(p.payload, code);
  p.payload[2] = static_cast<uint8_t>(od_->get(row_[k1001]));
  if (info != nullptr) {
    memcpy(&p.payload[3], info, 5);
  } else {
    memset(&p.payload[3], 0, 5);
  }
  ++queue_count_;
}

void EmcyProducer::raise(uint16_t code, uint8_t register_bits, const uint8_t* info) {
  if (active(code)) return;
  if (active_count_ == kMaxActive) {
    // Still tell the network; the set of active errors is full.
    ++overflows_;
  } else {
    active_[active_count_].code = code;
    active_[active_count_].bits = register_bits;
    ++active_count_;
  }
  update_register();
  push_history(code, info);
  enqueue(code, info);
}

void EmcyProducer::report(uint16_t code, bool on, uint8_t register_bits) {
  if (on) {
    raise(code, register_bits);
  } else {
    clear(code);
  }
}

void EmcyProducer::clear(uint16_t code) {
  for (uint8_t i = 0; i < active_count_; ++i) {
    if (active_[i].code != code) continue;
    active_[i] = active_[active_count_ - 1];
    --active_count_;
    update_register();
    if (active_count_ == 0) enqueue(kEmcyErrorReset, nullptr);
    return;
  }
}

void EmcyProducer::next_deadline(NextDeadline& d, bool allowed) const {
  if (inhibit_running_) {
    d.at(inhibit_until_us_);
  } else if (allowed && queue_count_ != 0) {
    d.now();
  }
}

void EmcyProducer::process(uint32_t now_us, bool allowed, const CanSink& sink) {
  if (inhibit_running_ && time_reached(now_us, inhibit_until_us_)) inhibit_running_ = false;
  if (!allowed || queue_count_ == 0 || inhibit_running_) return;
  const uint32_t cob = od_->get(row_[k1014]);
  if (cob & 0x80000000u) {  // EMCY not valid: nothing is sent, queue dropped
    queue_count_ = 0;
    return;
  }
  const Pending& p = queue_[queue_head_];
  // Port busy: try again next time.
  if (!send_frame(sink, static_cast<uint16_t>(cob & 0x7FFu), 8, p.payload)) return;
  queue_head_ = static_cast<uint8_t>((queue_head_ + 1) % kQueueLength);
  --queue_count_;
  const uint32_t inhibit_us = od_->get(row_[k1015]) * 100u;
  if (inhibit_us != 0) {
    inhibit_running_ = true;
    inhibit_until_us_ = now_us + inhibit_us;
  }
}

SdoAbort EmcyProducer::on_write(uint16_t index, uint8_t sub, const uint8_t* data, bool apply) {
  if (index == 0x1003) {
    // Only sub 0 is writable, and only with 0: clears the history.
    if (sub != 0 || data[0] != 0) return kAbortInvalidValue;
    for (uint8_t s = 1; apply && s <= kErrorHistoryLength; ++s) {
      od_->set(static_cast<uint16_t>(row_[k1003] + s), 0);
    }
    return kSdoOk;
  }
  // 1014h follows the rules of a PDO COB-ID (bit 31 = not valid): 11-bit
  // ids only, no restricted CAN-ID while valid (CiA 301 §7.3.5), and the
  // CAN-ID of a valid EMCY changes only after it is made invalid.
  if (index == 0x1014) return pdo_check_cob_id(od_->get(row_[k1014]), le32(data));
  return kSdoOk;
}

}  // namespace canopen
}  // namespace mb2co
