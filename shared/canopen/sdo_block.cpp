#include "canopen/sdo_block.h"

#include <string.h>

#include "canopen/frame_out.h"

namespace mb2co {
namespace canopen {

// Bit by bit: no 512-byte table (this code is also built for the AVR, as a
// portability check), and a 1 MiB transfer costs a few ms on the host.
uint16_t sdo_crc16(uint16_t crc, const uint8_t* data, uint32_t n) {
  for (uint32_t i = 0; i < n; ++i) {
    crc = static_cast<uint16_t>(crc ^ (static_cast<uint16_t>(data[i]) << 8));
    for (uint8_t b = 0; b < 8; ++b) {
      const uint16_t shifted = static_cast<uint16_t>(crc << 1);
      crc = (crc & 0x8000u) ? static_cast<uint16_t>(shifted ^ 0x1021u) : shifted;
    }
  }
  return crc;
}

// ---- sender -----------------------------------------------------------------

void BlockSender::start(const SdoData& data, uint32_t size) {
  data_ = data;
  size_ = size;
  acked_ = 0;
  crc_end_ = 0;
  crc_ = 0;
  blksize_ = 0;
  sent_ = 0;
  last_seq_ = 0;
  finished_ = false;
}

void BlockSender::begin_sub_block(uint8_t blksize) {
  blksize_ = blksize;
  sent_ = 0;
  last_seq_ = 0;
}

SdoAbort BlockSender::pump(uint16_t cob_id, const CanSink& sink) {
  while (pending()) {
    const uint32_t offset = acked_ + static_cast<uint32_t>(sent_) * kBlockSegmentBytes;
    const uint32_t left = size_ - offset;
    const uint8_t n = left < kBlockSegmentBytes ? static_cast<uint8_t>(left) : kBlockSegmentBytes;
    const bool last = left <= kBlockSegmentBytes;
    const uint8_t seq = static_cast<uint8_t>(sent_ + 1);
    uint8_t frame[8] = {static_cast<uint8_t>(seq | (last ? 0x80 : 0)), 0, 0, 0, 0, 0, 0, 0};
    if (n != 0) {
      const SdoAbort code = data_.read(data_.ctx, offset, &frame[1], n);
      if (code != kSdoOk) return code;
    }
    if (!send_frame(sink, cob_id, 8, frame)) return kSdoOk;  // pending() stays true: later
    if (offset + n > crc_end_) {
      const uint32_t skip = crc_end_ - offset;  // bytes of a resent segment already counted
      crc_ = sdo_crc16(crc_, &frame[1 + skip], n - skip);
      crc_end_ = offset + n;
    }
    sent_ = seq;
    if (last) last_seq_ = seq;
  }
  return kSdoOk;
}

SdoAbort BlockSender::on_ack(uint8_t ackseq, uint8_t blksize) {
  if (ackseq > sent_) return kAbortSequence;
  if (blksize == 0 || blksize > kBlockSizeMax) return kAbortBlockSize;
  if (last_seq_ != 0 && ackseq >= last_seq_) {
    acked_ = size_;
    finished_ = true;
  } else {
    acked_ += static_cast<uint32_t>(ackseq) * kBlockSegmentBytes;
  }
  begin_sub_block(blksize);
  return kSdoOk;
}

uint8_t BlockSender::unused() const {
  const uint8_t r = static_cast<uint8_t>(size_ % kBlockSegmentBytes);
  if (size_ == 0) return kBlockSegmentBytes;  // one segment, no data
  return r == 0 ? 0 : static_cast<uint8_t>(kBlockSegmentBytes - r);
}

// ---- receiver ---------------------------------------------------------------

void BlockReceiver::start(const SdoData& data, uint32_t limit, SdoAbort over_code, uint8_t blksize) {
  data_ = data;
  limit_ = limit;
  stored_ = 0;
  over_code_ = over_code;
  crc_ = 0;
  seq_ = 0;
  blksize_ = blksize;
  held_valid_ = false;
  last_ = false;
}

SdoAbort BlockReceiver::store(const uint8_t* bytes, uint8_t n) {
  if (n > limit_ - stored_) return over_code_;  // stored_ <= limit_ always
  if (n == 0) return kSdoOk;
  const SdoAbort code = data_.write(data_.ctx, stored_, bytes, n);
  if (code != kSdoOk) return code;
  crc_ = sdo_crc16(crc_, bytes, n);
  stored_ += n;
  return kSdoOk;
}

SdoAbort BlockReceiver::on_segment(const CanFrame& f, bool* ack) {
  const uint8_t seqno = f.data[0] & 0x7F;
  const bool c = (f.data[0] & 0x80) != 0;
  *ack = false;
  if (!last_ && seqno == seq_ + 1 && seqno <= blksize_) {
    if (held_valid_) {
      const SdoAbort code = store(held_, kBlockSegmentBytes);
      if (code != kSdoOk) return code;
    }
    memcpy(held_, &f.data[1], kBlockSegmentBytes);
    held_valid_ = true;
    seq_ = seqno;
    last_ = c;
  }
  // The sub-block ends with its last seqno or the last segment, whether or
  // not everything before it arrived: the ack tells the sender what did.
  *ack = c || seqno >= blksize_;
  return kSdoOk;
}

SdoAbort BlockReceiver::finish(uint8_t unused) {
  if (!last_ || !held_valid_) return kAbortCommand;
  held_valid_ = false;
  return store(held_, static_cast<uint8_t>(kBlockSegmentBytes - (unused & 0x07)));
}

}  // namespace canopen
}  // namespace mb2co
