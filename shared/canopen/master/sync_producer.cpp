#include "canopen/master/sync_producer.h"

#include "canopen/frame_out.h"

namespace mb2co {
namespace canopen {

bool SyncProducer::configure(uint32_t cob_id, uint32_t period_us, uint8_t overflow) {
  if ((cob_id & 0x20000000u) || overflow == 1 || overflow > 240) return false;
  cob_id_ = static_cast<uint16_t>(cob_id & 0x7FFu);
  period_us_ = period_us;
  overflow_ = overflow;
  counter_ = 0;
  restart_ = true;
  return true;
}

bool SyncProducer::process(uint32_t now_us, const CanSink& sink, uint8_t* counter) {
  if (period_us_ == 0) {
    restart_ = true;
    return false;
  }
  if (restart_) {
    restart_ = false;
    period_start_us_ = now_us;
    return false;
  }
  const uint32_t elapsed_us = now_us - period_start_us_;
  if (elapsed_us < period_us_) return false;
  // Whole periods only, and no burst after a pause longer than one period.
  period_start_us_ = elapsed_us - period_us_ < period_us_ ? period_start_us_ + period_us_ : now_us;
  if (overflow_ != 0) counter_ = static_cast<uint8_t>(counter_ >= overflow_ ? 1 : counter_ + 1);
  const uint8_t count = overflow_ != 0 ? counter_ : 0;
  if (counter != nullptr) *counter = count;
  if (send_frame(sink, cob_id_, overflow_ != 0 ? 1 : 0, &counter_)) return true;
  if (send_failures_ != 0xFFFF) ++send_failures_;
  return false;
}

void SyncProducer::next_deadline(NextDeadline& d) const {
  if (period_us_ == 0) return;
  if (restart_) return d.now();
  const uint32_t elapsed_us = d.now_us() - period_start_us_;
  d.in(elapsed_us < period_us_ ? period_us_ - elapsed_us : 0);
}

}  // namespace canopen
}  // namespace mb2co
