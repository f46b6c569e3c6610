#include "canopen/sdo_client.h"

#include <string.h>

#include "canopen/frame_out.h"
#include "canopen/od.h"

namespace mb2co {
namespace canopen {

void SdoClient::init(uint8_t server_node_id) {
  request_id_ = static_cast<uint16_t>(0x600u + server_node_id);
  response_id_ = static_cast<uint16_t>(0x580u + server_node_id);
  state_ = kStIdle;
  result_ = kSdoOk;
}

SdoClient::Status SdoClient::status() const {
  if (state_ == kStIdle) return kIdle;
  if (state_ == kStDone) return kDone;
  if (state_ == kStFailed) return kFailed;
  return kBusy;
}

// ---- the caller's buffer as SdoData ------------------------------------------

SdoAbort SdoClient::buffer_write(void* ctx, uint32_t offset, const uint8_t* data, uint16_t n) {
  SdoClient& c = *static_cast<SdoClient*>(ctx);
  if (offset > c.capacity_ || n > c.capacity_ - offset) return kAbortOutOfMemory;
  memcpy(c.buffer_ + offset, data, n);
  return kSdoOk;
}

SdoAbort SdoClient::buffer_read(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n) {
  const SdoClient& c = *static_cast<const SdoClient*>(ctx);
  memcpy(buf, c.buffer_ + offset, n);
  return kSdoOk;
}

// ---- starting ---------------------------------------------------------------

void SdoClient::begin(uint16_t index, uint8_t sub, uint32_t now_us) {
  index_ = index;
  sub_ = sub;
  pos_ = 0;
  toggle_ = 0;
#if MB2CO_CONFIG_SDO_BLOCK
  crc_ = false;
  repeats_ = 0;
#endif
  server_abort_ = false;
  result_ = kSdoOk;
  deadline_us_ = now_us + timeout_us_;
}

void SdoClient::send(const CanSink& sink, const uint8_t data[8]) {
  send_frame(sink, request_id_, 8, data);
}

void SdoClient::send_mux(const CanSink& sink, uint8_t cmd, uint32_t value) {
  uint8_t bytes[7];
  sdo_mux_bytes(bytes, index_, sub_, value);
  send_sdo(sink, cmd, bytes, 7, request_id_);
}

bool SdoClient::start_upload(uint16_t index, uint8_t sub, SdoMode mode, uint8_t* buf, uint32_t capacity,
                             uint32_t now_us, const CanSink& sink) {
  if (busy()) return false;
  const SdoData out = {&SdoClient::buffer_write, &SdoClient::buffer_read, this};
  if (!start_upload(index, sub, mode, out, capacity, now_us, sink)) return false;
  buffer_ = buf;
  return true;
}

bool SdoClient::start_upload(uint16_t index, uint8_t sub, SdoMode mode, const SdoData& out, uint32_t capacity,
                             uint32_t now_us, const CanSink& sink) {
  if (busy()) return false;
  begin(index, sub, now_us);
  data_ = out;
  buffer_ = nullptr;
  capacity_ = capacity;
  size_ = 0;
  size_known_ = false;
#if MB2CO_CONFIG_SDO_BLOCK
  if (mode == kSdoBlock) {
    if (block_size_ == 0 || block_size_ > kBlockSizeMax) block_size_ = kBlockSizeMax;
    // ccs 5, cc = 1 (we check CRCs), cs = 0; blksize; pst.
    send_mux(sink, 0xA4, static_cast<uint32_t>(block_size_) | (static_cast<uint32_t>(pst_) << 8));
    state_ = kStBlockUploadInitiate;
    return true;
  }
#else
  (void)mode;  // every upload starts alike; the server picks expedited or segmented
#endif
  send_mux(sink, 0x40, 0);
  state_ = kStUploadInitiate;
  return true;
}

bool SdoClient::start_download(uint16_t index, uint8_t sub, SdoMode mode, const uint8_t* data, uint32_t size,
                               uint32_t now_us, const CanSink& sink) {
  if (busy()) return false;
  const SdoData in = {&SdoClient::buffer_write, &SdoClient::buffer_read, this};
  // The buffer is only read: buffer_write is never called for a download.
  buffer_ = const_cast<uint8_t*>(data);
  capacity_ = size;
  if (!start_download(index, sub, mode, in, size, now_us, sink)) return false;
  buffer_ = const_cast<uint8_t*>(data);
  return true;
}

bool SdoClient::start_download(uint16_t index, uint8_t sub, SdoMode mode, const SdoData& in, uint32_t size,
                               uint32_t now_us, const CanSink& sink) {
  if (busy()) return false;
  begin(index, sub, now_us);
  data_ = in;
  size_ = size;
  available_ = size;
  size_known_ = true;
  expedited_ = mode == kSdoAuto && size >= 1 && size <= 4;
#if MB2CO_CONFIG_SDO_BLOCK
  if (mode == kSdoBlock) {
    // ccs 6, cc = 1, s = 1, cs = 0; size.
    send_mux(sink, 0xC6, size);
    state_ = kStBlockDownloadInitiate;
    return true;
  }
#endif
  uint32_t value = size;  // segmented (21h): the size, indicated
  uint8_t cmd = 0x21;
  if (expedited_) {
    uint8_t bytes[4] = {0, 0, 0, 0};
    const SdoAbort code = data_.read(data_.ctx, 0, bytes, static_cast<uint16_t>(size));
    if (code != kSdoOk) {
      finish(code, false);  // nothing was sent: the server knows of no transfer
      return true;
    }
    value = le32(bytes);
    cmd = expedited_command(0x20, size);
  }
  send_mux(sink, cmd, value);
  state_ = kStDownloadInitiate;
  return true;
}

// ---- driving ----------------------------------------------------------------

void SdoClient::finish(SdoAbort code, bool by_server) {
  result_ = code;
  server_abort_ = by_server;
  state_ = code == kSdoOk ? kStDone : kStFailed;
}

void SdoClient::abort(SdoAbort code, const CanSink& sink) {
  if (!busy()) return;
  send_mux(sink, 0x80, code);
  finish(code, false);
}

void SdoClient::process(uint32_t now_us, const CanSink& sink) {
  if (!busy()) return;
#if MB2CO_CONFIG_SDO_BLOCK
  if (state_ == kStBlockDownloadSub && sender_.pending()) {
    const SdoAbort code = sender_.pump(request_id_, sink);
    if (code != kSdoOk) return abort(code, sink);
    // The answer may take the timeout from the sub-block's last segment on;
    // a sub-block sent again keeps the deadline of the last progress.
    if (!sender_.pending() && repeats_ == 0) deadline_us_ = now_us + timeout_us_;
    return;
  }
#endif
  if (!time_reached(now_us, deadline_us_)) return;
  if (timeout_abort_sent_) return abort(kAbortTimeout, sink);
  finish(kAbortTimeout, false);
}

void SdoClient::next_deadline(NextDeadline& d) const {
  if (!busy()) return;
#if MB2CO_CONFIG_SDO_BLOCK
  if (state_ == kStBlockDownloadSub && sender_.pending()) return d.now();
#endif
  d.at(deadline_us_);
}

void SdoClient::on_frame(const CanFrame& f, uint32_t now_us, const CanSink& sink) {
  if (f.id != response_id_ || f.rtr() || f.extended() || f.dlc != 8 || !busy()) return;
  // 80h is the abort frame in every state (no block segment has seqno 0).
  if (f.data[0] == 0x80) return finish(static_cast<SdoAbort>(le32(&f.data[4])), true);
  const uint32_t pos_before = pos_;
  const State state_before = state_;
  const SdoAbort code = on_response(f, sink);
  if (code != kSdoOk) return abort(code, sink);
  // Only progress restarts the timeout: bytes moved or a step of the
  // protocol. A frame that moves nothing (an empty segment, a block segment
  // out of sequence, an ack of nothing) leaves it running, so a server that
  // answers forever without progress ends like a silent one (05040000h).
  // While a sub-block goes out the timeout waits for its ack: it starts
  // once the last segment is sent (process()).
  if (pos_ != pos_before || state_ != state_before) deadline_us_ = now_us + timeout_us_;
}

bool SdoClient::mux_matches(const CanFrame& f) const {
  return le16(&f.data[1]) == index_ && f.data[3] == sub_;
}

SdoAbort SdoClient::on_response(const CanFrame& f, const CanSink& sink) {
  const uint8_t cmd = f.data[0];
  switch (state_) {
    case kStDownloadInitiate:
      if (cmd != 0x60) return kAbortCommand;
      if (!mux_matches(f)) return kAbortIncompatible;
      if (expedited_) {
        pos_ = size_;
        succeed();
        return kSdoOk;
      }
      state_ = kStDownloadSegment;
      send_download_segment(sink);
      return kSdoOk;
    case kStDownloadSegment:
      if ((cmd & 0xE0) != 0x20) return kAbortCommand;
      if (!toggle_matches(cmd, toggle_)) return kAbortToggle;
      pos_ += seg_n_;
      if (pos_ == size_) {
        succeed();
        return kSdoOk;
      }
      toggle_ ^= kSegmentToggle;
      send_download_segment(sink);
      return kSdoOk;
    case kStUploadInitiate:
      return on_upload_initiate(f, sink);
    case kStUploadSegment:
      return on_upload_segment(f, sink);
#if MB2CO_CONFIG_SDO_BLOCK
    case kStBlockDownloadInitiate:
    case kStBlockDownloadSub:
    case kStBlockDownloadEnd:
      return on_block_download(f, sink);
    default:
      return on_block_upload(f, sink);
#else
    default:
      return kAbortCommand;  // busy() holds: one of the states above
#endif
  }
}

void SdoClient::set_available(uint32_t end, const CanSink& sink) {
  available_ = end;
  if (state_ != kStDownloadWaiting) return;
  state_ = kStDownloadSegment;
  send_download_segment(sink);
}

// A segment is sent once; if it is lost the server's silence times out.
void SdoClient::send_download_segment(const CanSink& sink) {
  const uint32_t left = size_ - pos_;
  seg_n_ = left < kSegmentBytes ? static_cast<uint8_t>(left) : kSegmentBytes;
  if (pos_ + seg_n_ > available_) {
    state_ = kStDownloadWaiting;  // set_available() sends it
    return;
  }
  uint8_t bytes[kSegmentBytes];
  if (seg_n_ != 0) {
    const SdoAbort code = data_.read(data_.ctx, pos_, bytes, seg_n_);
    if (code != kSdoOk) return abort(code, sink);
  }
  send_sdo(sink, segment_command(toggle_, seg_n_, left <= kSegmentBytes), bytes, seg_n_, request_id_);
}

void SdoClient::send_upload_request(const CanSink& sink) {
  send_sdo(sink, static_cast<uint8_t>(0x60 | toggle_), nullptr, 0, request_id_);
}

// The plain upload's initiate answer; also the block upload's when the
// server switched protocols (size <= pst).
SdoAbort SdoClient::on_upload_initiate(const CanFrame& f, const CanSink& sink) {
  const uint8_t cmd = f.data[0];
  if ((cmd & 0xE0) != 0x40) return kAbortCommand;
  if (!mux_matches(f)) return kAbortIncompatible;
  const bool indicated = (cmd & 0x01) != 0;
  if (cmd & 0x02) {  // expedited: n unused bytes when indicated, else 4 bytes
    const uint8_t n = expedited_size(cmd);
    size_ = n;
    size_known_ = true;
    if (n > capacity_) return kAbortOutOfMemory;
    const SdoAbort code = data_.write(data_.ctx, 0, &f.data[4], n);
    if (code != kSdoOk) return code;
    pos_ = n;
    succeed();
    return kSdoOk;
  }
  size_known_ = indicated;
  size_ = indicated ? le32(&f.data[4]) : 0;
  if (indicated && size_ > capacity_) return kAbortOutOfMemory;
  toggle_ = 0;
  state_ = kStUploadSegment;
  send_upload_request(sink);
  return kSdoOk;
}

SdoAbort SdoClient::on_upload_segment(const CanFrame& f, const CanSink& sink) {
  const uint8_t cmd = f.data[0];
  if ((cmd & 0xE0) != 0x00) return kAbortCommand;
  if (!toggle_matches(cmd, toggle_)) return kAbortToggle;
  const uint8_t n = segment_size(cmd);
  // More than announced is the server's error (06070012h), more than we
  // hold ours (05040005h); an announced size above the capacity was
  // refused at the initiate, so the tighter limit decides.
  const uint32_t limit = size_known_ ? size_ : capacity_;
  if (n > limit - pos_) return size_known_ ? kAbortTooLong : kAbortOutOfMemory;
  if (n != 0) {
    const SdoAbort code = data_.write(data_.ctx, pos_, &f.data[1], n);
    if (code != kSdoOk) return code;
  }
  pos_ += n;
  if (segment_last(cmd)) {
    if (size_known_ && pos_ != size_) return kAbortTooShort;  // less than announced
    size_ = pos_;
    size_known_ = true;
    succeed();
    return kSdoOk;
  }
  toggle_ ^= kSegmentToggle;
  send_upload_request(sink);
  return kSdoOk;
}

// ---- block transfer -----------------------------------------------------------
#if MB2CO_CONFIG_SDO_BLOCK

SdoAbort SdoClient::count_repeat(bool repeat) {
  if (!repeat) {
    repeats_ = 0;
    return kSdoOk;
  }
  // Sequence numbers that never get through: 05040003h (invalid sequence
  // number) rather than waiting for the timeout with the bus flooded.
  return ++repeats_ > kBlockRepeatsMax ? kAbortSequence : kSdoOk;
}

SdoAbort SdoClient::on_block_download(const CanFrame& f, const CanSink& sink) {
  const uint8_t cmd = f.data[0];
  if ((cmd & 0xE0) != 0xA0) return kAbortCommand;
  const uint8_t ss = cmd & 0x03;
  if (state_ == kStBlockDownloadInitiate && ss == 0) {
    if (!mux_matches(f)) return kAbortIncompatible;
    const uint8_t blksize = f.data[4];
    if (blksize == 0 || blksize > kBlockSizeMax) return kAbortBlockSize;
    crc_ = (cmd & 0x04) != 0;  // we always offer it: the server decides
    sender_.start(data_, size_);
    sender_.begin_sub_block(blksize);
    state_ = kStBlockDownloadSub;
    return sender_.pump(request_id_, sink);
  }
  if (state_ == kStBlockDownloadSub && ss == 2 && !sender_.pending()) {
    const bool repeat = f.data[1] < sender_.sent();
    const SdoAbort code = sender_.on_ack(f.data[1], f.data[2]);
    if (code != kSdoOk) return code;
    pos_ = sender_.acked();
    if (!sender_.finished()) {
      const SdoAbort bound = count_repeat(repeat);
      return bound != kSdoOk ? bound : sender_.pump(request_id_, sink);
    }
    uint8_t d[8] = {static_cast<uint8_t>(0xC1 | (sender_.unused() << 2)), 0, 0, 0, 0, 0, 0, 0};
    if (crc_) put_le16(&d[1], sender_.crc());
    send(sink, d);
    state_ = kStBlockDownloadEnd;
    return kSdoOk;
  }
  if (state_ == kStBlockDownloadEnd && ss == 1) {
    succeed();
    return kSdoOk;
  }
  return kAbortCommand;
}

SdoAbort SdoClient::on_block_upload(const CanFrame& f, const CanSink& sink) {
  const uint8_t cmd = f.data[0];
  if (state_ == kStBlockUploadInitiate) {
    if ((cmd & 0xE0) == 0x40) {  // the server switched to a plain upload
      state_ = kStUploadInitiate;
      return on_upload_initiate(f, sink);
    }
    if ((cmd & 0xE1) != 0xC0) return kAbortCommand;
    if (!mux_matches(f)) return kAbortIncompatible;
    crc_ = (cmd & 0x04) != 0;
    size_known_ = (cmd & 0x02) != 0;
    size_ = size_known_ ? le32(&f.data[4]) : 0;
    if (size_known_ && size_ > capacity_) return kAbortOutOfMemory;
    // The tighter limit decides the code: more than announced is the
    // server's error (06070012h), more than we hold is ours (05040005h);
    // an announced size above the capacity was refused above.
    if (size_known_) {
      receiver_.start(data_, size_, kAbortTooLong, block_size_);
    } else {
      receiver_.start(data_, capacity_, kAbortOutOfMemory, block_size_);
    }
    state_ = kStBlockUploadSub;
    const uint8_t d[8] = {0xA3, 0, 0, 0, 0, 0, 0, 0};
    send(sink, d);
    return kSdoOk;
  }
  if (state_ == kStBlockUploadSub) {
    bool ack = false;
    SdoAbort code = receiver_.on_segment(f, &ack);
    if (code != kSdoOk) return code;
    pos_ = receiver_.received();
    // A full segment (c = 0) beyond the limit ends the transfer at once.
    if (size_known_ && receiver_.beyond(size_)) return kAbortTooLong;
    if (receiver_.beyond(capacity_)) return kAbortOutOfMemory;
    if (!ack) return kSdoOk;
    code = count_repeat(!receiver_.complete() && receiver_.ackseq() < block_size_);
    if (code != kSdoOk) return code;
    const uint8_t d[8] = {0xA2, receiver_.ackseq(), block_size_, 0, 0, 0, 0, 0};
    send(sink, d);
    receiver_.next_sub_block(block_size_);
    if (receiver_.complete()) state_ = kStBlockUploadEnd;
    return kSdoOk;
  }
  // kStBlockUploadEnd: the server's end frame.
  if ((cmd & 0xE3) != 0xC1) return kAbortCommand;
  const SdoAbort code = receiver_.finish(static_cast<uint8_t>((cmd >> 2) & 0x07));
  if (code != kSdoOk) return code;
  if (size_known_ && receiver_.received() != size_) return kAbortTooShort;
  if (crc_ && le16(&f.data[1]) != receiver_.crc()) return kAbortCrc;
  size_ = receiver_.received();
  pos_ = size_;
  size_known_ = true;
  const uint8_t d[8] = {0xA1, 0, 0, 0, 0, 0, 0, 0};
  send(sink, d);
  succeed();
  return kSdoOk;
}
#endif  // MB2CO_CONFIG_SDO_BLOCK

}  // namespace canopen
}  // namespace mb2co
