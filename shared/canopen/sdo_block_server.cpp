// The SdoServer's host-only part (MB2CO_CONFIG_SDO_BLOCK, sdo_server.h): block
// upload and download (CiA 301 §7.2.4.3.9-16) of OD values and of domain
// objects, and expedited/segmented transfers of domain objects. Without the
// macro this file is empty, so the AVR images stay as they are.
#include "canopen/sdo_server.h"

#if MB2CO_CONFIG_SDO_BLOCK

#include <string.h>

#include "canopen/frame_out.h"

namespace mb2co {
namespace canopen {

static const uint32_t kNoLimit = 0xFFFFFFFFu;

// A frame without multiplexer: command byte, then `b1`, `b2`, zeros
// (block acks, end frames, segment acks: their other bytes are reserved).
static void send_short(const CanSink& sink, uint8_t node_id, uint8_t cmd, uint8_t b1, uint8_t b2) {
  const uint8_t d[8] = {cmd, b1, b2, 0, 0, 0, 0, 0};
  send_frame(sink, static_cast<uint16_t>(0x580u + node_id), 8, d);
}

bool SdoServer::on_host_frame(const CanFrame& f, const CanSink& sink, SdoAbort* code) {
  // During a block download every frame is a segment, except the abort.
  if (state_ == kBlockDownloadSub && f.data[0] != 0x80) {
    *code = block_download_segment(f, sink);
    return true;
  }
  switch (f.data[0] >> 5) {
    case 6:
      if (!block_) return false;  // 05040001h, as on the AVR
      *code = block_download(f, sink);
      return true;
    case 5:
      if (!block_) return false;
      *code = block_upload(f, sink);
      return true;
    case 1:
      if (!domain_owns(f)) return false;
      *code = domain_download(f, sink);
      return true;
    case 2:
      if (!domain_owns(f)) return false;
      *code = domain_upload(f, sink);
      return true;
    case 0:
      if (state_ != kDomainDownloading) return false;
      *code = domain_download_segment(f, sink);
      return true;
    case 3:
      if (state_ != kDomainUploading) return false;
      *code = domain_upload_segment(f, sink);
      return true;
    default:
      return false;
  }
}

bool SdoServer::domain_owns(const CanFrame& f) const {
  return domain_ != nullptr && domain_->owns(domain_->ctx, le16(&f.data[1]), f.data[3]);
}

// ---- the object as a byte stream ------------------------------------------------

SdoData SdoServer::stream() {
  if (in_domain_) return SdoData{&SdoServer::domain_write, &SdoServer::domain_read, this};
  return SdoData{&SdoServer::buffer_write, &SdoServer::buffer_read, this};
}

SdoAbort SdoServer::buffer_write(void* ctx, uint32_t offset, const uint8_t* data, uint16_t n) {
  SdoServer& s = *static_cast<SdoServer*>(ctx);
  if (offset > kBufferSize || n > kBufferSize - offset) return kAbortTooLong;
  memcpy(&s.buffer_[offset], data, n);
  s.length_ = static_cast<uint8_t>(offset + n);
  return kSdoOk;
}

SdoAbort SdoServer::buffer_read(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n) {
  const SdoServer& s = *static_cast<const SdoServer*>(ctx);
  if (offset > s.length_ || n > s.length_ - offset) return kAbortGeneral;
  memcpy(buf, &s.buffer_[offset], n);
  return kSdoOk;
}

SdoAbort SdoServer::domain_write(void* ctx, uint32_t offset, const uint8_t* data, uint16_t n) {
  const SdoServer& s = *static_cast<const SdoServer*>(ctx);
  return s.domain_->write(s.domain_->ctx, s.index_, s.sub_, offset, data, n);
}

SdoAbort SdoServer::domain_read(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n) {
  const SdoServer& s = *static_cast<const SdoServer*>(ctx);
  return s.domain_->read(s.domain_->ctx, s.index_, s.sub_, offset, buf, n);
}

// ---- expedited and segmented transfers of domain objects --------------------------

SdoAbort SdoServer::domain_download(const CanFrame& f, const CanSink& sink) {
  state_ = kIdle;
  take_multiplexer(f);
  in_domain_ = true;
  const bool indicated = (f.data[0] & 0x01) != 0;
  if (f.data[0] & 0x02) {  // expedited: begin, write and commit at once
    const uint8_t len = expedited_size(f.data[0]);
    SdoAbort code = domain_->begin(domain_->ctx, index_, sub_, len, true);
    if (code == kSdoOk) code = domain_write(this, 0, &f.data[4], len);
    if (code == kSdoOk) code = domain_->commit(domain_->ctx, index_, sub_, len);
    if (code != kSdoOk) return code;
    respond(sink, 0x60, 0);
    return kSdoOk;
  }
  size_indicated_ = indicated;
  announced_ = indicated ? le32(&f.data[4]) : 0;
  const SdoAbort code = domain_->begin(domain_->ctx, index_, sub_, announced_, indicated);
  if (code != kSdoOk) return code;
  pos_ = 0;
  toggle_ = 0;
  state_ = kDomainDownloading;
  respond(sink, 0x60, 0);
  return kSdoOk;
}

SdoAbort SdoServer::domain_download_segment(const CanFrame& f, const CanSink& sink) {
  if (!toggle_matches(f.data[0], toggle_)) return kAbortToggle;
  const uint8_t count = segment_size(f.data[0]);
  if (size_indicated_ && count > announced_ - pos_) return kAbortTooLong;
  if (count != 0) {
    const SdoAbort code = domain_write(this, pos_, &f.data[1], count);
    if (code != kSdoOk) return code;
  }
  pos_ += count;
  const uint8_t ack = static_cast<uint8_t>(0x20 | toggle_);
  toggle_ ^= kSegmentToggle;
  if (segment_last(f.data[0])) {
    if (size_indicated_ && pos_ != announced_) return kAbortTooShort;
    const SdoAbort code = domain_->commit(domain_->ctx, index_, sub_, pos_);
    if (code != kSdoOk) return code;
    state_ = kIdle;
  }
  respond_short(sink, ack);
  return kSdoOk;
}

SdoAbort SdoServer::domain_upload(const CanFrame& f, const CanSink& sink) {
  state_ = kIdle;
  take_multiplexer(f);
  in_domain_ = true;
  size_ = domain_->size(domain_->ctx, index_, sub_);
  if (size_ >= 1 && size_ <= 4) {
    uint8_t payload[4] = {0, 0, 0, 0};
    const SdoAbort code = domain_read(this, 0, payload, static_cast<uint16_t>(size_));
    if (code != kSdoOk) return code;
    respond(sink, expedited_command(0x40, size_), le32(payload));
    return kSdoOk;
  }
  pos_ = 0;
  toggle_ = 0;
  state_ = kDomainUploading;
  respond(sink, 0x41, size_);
  return kSdoOk;
}

SdoAbort SdoServer::domain_upload_segment(const CanFrame& f, const CanSink& sink) {
  if (!toggle_matches(f.data[0], toggle_)) return kAbortToggle;
  const uint32_t left = size_ - pos_;
  const uint8_t count = left < kSegmentBytes ? static_cast<uint8_t>(left) : kSegmentBytes;
  const bool last = left <= kSegmentBytes;
  uint8_t d[8] = {segment_command(toggle_, count, last), 0, 0, 0, 0, 0, 0, 0};
  if (count != 0) {
    const SdoAbort code = domain_read(this, pos_, &d[1], count);
    if (code != kSdoOk) return code;
  }
  send_frame(sink, static_cast<uint16_t>(0x580u + node_id_), 8, d);
  pos_ += count;
  toggle_ ^= kSegmentToggle;
  if (last) state_ = kIdle;
  return kSdoOk;
}

// ---- block download ------------------------------------------------------------------

SdoAbort SdoServer::block_download(const CanFrame& f, const CanSink& sink) {
  const uint8_t cmd = f.data[0];
  if ((cmd & 0x01) == 0) {  // initiate: 110 00 cc s 0
    state_ = kIdle;
    take_multiplexer(f);
    size_indicated_ = (cmd & 0x02) != 0;
    announced_ = size_indicated_ ? le32(&f.data[4]) : 0;
    uint32_t limit = size_indicated_ ? announced_ : kNoLimit;
    in_domain_ = domain_owns(f);
    if (in_domain_) {
      const SdoAbort code = domain_->begin(domain_->ctx, index_, sub_, announced_, size_indicated_);
      if (code != kSdoOk) return code;
    } else {
      // The same checks as a segmented download of an OD value.
      uint16_t row = 0;
      const SdoAbort code = od_->check_write(index_, sub_, &row);
      if (code != kSdoOk) return code;
      const uint16_t capacity = od_->capacity_of(row);
      const bool is_string = od_->attr(row) & kAttrString;
      if (size_indicated_ && (announced_ > capacity || announced_ > kBufferSize)) return kAbortTooLong;
      if (size_indicated_ && announced_ < capacity && !is_string) return kAbortTooShort;
      if (!size_indicated_) limit = capacity < kBufferSize ? capacity : kBufferSize;
      length_ = 0;
    }
    if (block_size_ == 0 || block_size_ > kBlockSizeMax) block_size_ = kBlockSizeMax;
    crc_ = (cmd & 0x04) != 0;
    receiver_.start(stream(), limit, kAbortTooLong, block_size_);
    state_ = kBlockDownloadSub;
    respond(sink, 0xA4, block_size_);  // 101 00 sc=1 00: we check CRCs when the client does
    return kSdoOk;
  }
  // End: 110 n 0 1, CRC.
  if (state_ != kBlockDownloadEnd || (cmd & 0xE3) != 0xC1) return kAbortCommand;
  SdoAbort code = receiver_.finish(static_cast<uint8_t>((cmd >> 2) & 0x07));
  if (code != kSdoOk) return code;
  const uint32_t n = receiver_.received();
  if (size_indicated_ && n != announced_) return kAbortTypeMismatch;
  if (crc_ && le16(&f.data[1]) != receiver_.crc()) return kAbortCrc;
  // Only now does the data reach the object, in one piece.
  code = in_domain_ ? domain_->commit(domain_->ctx, index_, sub_, n)
                    : od_->write(index_, sub_, buffer_, static_cast<uint16_t>(n));
  if (code != kSdoOk) return code;
  state_ = kIdle;
  send_short(sink, node_id_, 0xA1, 0, 0);
  return kSdoOk;
}

SdoAbort SdoServer::block_download_segment(const CanFrame& f, const CanSink& sink) {
  bool ack = false;
  const SdoAbort code = receiver_.on_segment(f, &ack);
  if (code != kSdoOk || !ack) return code;
  send_short(sink, node_id_, 0xA2, receiver_.ackseq(), block_size_);
  receiver_.next_sub_block(block_size_);
  if (receiver_.complete()) state_ = kBlockDownloadEnd;
  return kSdoOk;
}

// ---- block upload -----------------------------------------------------------------------

SdoAbort SdoServer::block_upload(const CanFrame& f, const CanSink& sink) {
  const uint8_t cmd = f.data[0];
  switch (cmd & 0x03) {
    case 0: {  // initiate: 101 00 cc 00, blksize, pst
      state_ = kIdle;
      take_multiplexer(f);
      const uint8_t blksize = f.data[4];
      const uint8_t pst = f.data[5];
      if (blksize == 0 || blksize > kBlockSizeMax) return kAbortBlockSize;
      in_domain_ = domain_owns(f);
      uint32_t size = 0;
      if (in_domain_) {
        size = domain_->size(domain_->ctx, index_, sub_);
      } else {
        uint16_t len = 0;
        const SdoAbort code = od_->read(index_, sub_, buffer_, kBufferSize, &len);
        if (code != kSdoOk) return code;
        length_ = static_cast<uint8_t>(len);
        size = len;
      }
      // The protocol switch: small enough for a plain upload, as the client allows.
      if (pst != 0 && size <= pst) return in_domain_ ? domain_upload(f, sink) : initiate_upload(sink);
      size_ = size;
      crc_ = (cmd & 0x04) != 0;
      sender_.start(stream(), size);
      sender_.begin_sub_block(blksize);
      state_ = kBlockUploadStart;
      respond(sink, 0xC6, size);  // 110 00 sc=1 s=1 0
      return kSdoOk;
    }
    case 3:  // start
      if (state_ != kBlockUploadStart) return kAbortCommand;
      state_ = kBlockUploadSub;
      return pump(sink);
    case 2: {  // ack, blksize
      if (state_ != kBlockUploadSub || sender_.pending()) return kAbortCommand;
      const SdoAbort code = sender_.on_ack(f.data[1], f.data[2]);
      if (code != kSdoOk) return code;
      if (!sender_.finished()) return pump(sink);
      const uint16_t crc = crc_ ? sender_.crc() : static_cast<uint16_t>(0);
      send_short(sink, node_id_, static_cast<uint8_t>(0xC1 | (sender_.unused() << 2)),
                 static_cast<uint8_t>(crc), static_cast<uint8_t>(crc >> 8));
      state_ = kBlockUploadEnd;
      return kSdoOk;
    }
    default:  // 1: the client's end response
      if (state_ != kBlockUploadEnd) return kAbortCommand;
      state_ = kIdle;
      return kSdoOk;
  }
}

SdoAbort SdoServer::pump(const CanSink& sink) {
  return sender_.pump(static_cast<uint16_t>(0x580u + node_id_), sink);
}

void SdoServer::process_block(const CanSink& sink) {
  const SdoAbort code = pump(sink);
  if (code != kSdoOk) abort(sink, code);
}

}  // namespace canopen
}  // namespace mb2co

#endif  // MB2CO_CONFIG_SDO_BLOCK
