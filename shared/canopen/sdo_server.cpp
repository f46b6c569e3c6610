#include "canopen/sdo_server.h"

#include <string.h>

#include "canopen/clock.h"
#include "canopen/frame_out.h"

namespace mb2co {
namespace canopen {

// Command specifiers (byte 0 bits 7..5).
enum : uint8_t {
  kCcsDownloadSegment = 0,
  kCcsInitiateDownload = 1,
  kCcsInitiateUpload = 2,
  kCcsUploadSegment = 3,
  kCcsAbort = 4,
};

void SdoServer::init(ObjectDictionary* od, uint8_t node_id) {
  od_ = od;
  node_id_ = node_id;
  state_ = kIdle;
}

void SdoServer::respond(const CanSink& sink, uint8_t cmd, uint32_t value) {
  uint8_t bytes[7];
  sdo_mux_bytes(bytes, index_, sub_, value);
  send_sdo(sink, cmd, bytes, 7, static_cast<uint16_t>(0x580u + node_id_));
}

// A download segment response carries no multiplexer: bytes 1..7 are
// reserved and sent as 0 (CiA 301 §7.2.4.3.5).
void SdoServer::respond_short(const CanSink& sink, uint8_t cmd) {
  send_sdo(sink, cmd, nullptr, 0, static_cast<uint16_t>(0x580u + node_id_));
}

void SdoServer::abort(const CanSink& sink, SdoAbort code) {
  respond(sink, 0x80, code);
  state_ = kIdle;
}

void SdoServer::take_multiplexer(const CanFrame& f) {
  index_ = le16(&f.data[1]);
  sub_ = f.data[3];
}

void SdoServer::on_frame(const CanFrame& f, uint32_t now_us, const CanSink& sink) {
  if (f.rtr() || f.dlc != 8) return;
  const uint8_t ccs = static_cast<uint8_t>(f.data[0] >> 5);
  deadline_us_ = now_us + timeout_us_;
  SdoAbort code = kSdoOk;
#if MB2CO_CONFIG_SDO_BLOCK
  if (on_host_frame(f, sink, &code)) {
    if (code != kSdoOk) abort(sink, code);
    return;
  }
#endif
  // Every request but a segment and the client's abort names an object and
  // replaces any transfer in progress.
  if (ccs != kCcsDownloadSegment && ccs != kCcsUploadSegment && ccs != kCcsAbort) {
    state_ = kIdle;
    take_multiplexer(f);
  }
  switch (ccs) {
    case kCcsInitiateDownload:
      code = initiate_download(f, sink);
      break;
    case kCcsDownloadSegment:
      code = download_segment(f, sink);
      break;
    case kCcsInitiateUpload:
      code = initiate_upload(sink);
      break;
    case kCcsUploadSegment:
      code = upload_segment(f, sink);
      break;
    case kCcsAbort:
      state_ = kIdle;  // the client gave up: no answer
      break;
    default:  // 5, 6 (block transfer) and 7
      code = kAbortCommand;
      break;
  }
  if (code != kSdoOk) abort(sink, code);
}

void SdoServer::process(uint32_t now_us, const CanSink& sink) {
#if MB2CO_CONFIG_SDO_BLOCK
  if (state_ == kBlockUploadSub && sender_.pending()) return process_block(sink);
#endif
  if (state_ != kIdle && time_reached(now_us, deadline_us_)) abort(sink, kAbortTimeout);
}

// The initiate requests: on_frame() took their object as index_/sub_ and
// went idle (nothing else reads them before the answer).
SdoAbort SdoServer::initiate_download(const CanFrame& f, const CanSink& sink) {
  uint16_t row = 0;
  SdoAbort code = od_->check_write(index_, sub_, &row);
  if (code != kSdoOk) return code;
  const bool expedited = f.data[0] & 0x02;
  const bool indicated = f.data[0] & 0x01;
  const uint16_t capacity = od_->capacity_of(row);
  const bool is_string = od_->attr(row) & kAttrString;
  if (expedited) {
    uint16_t len = expedited_size(f.data[0]);
    if (!indicated && !is_string && capacity < 4)
      len = capacity;  // size not indicated: the object's own size
    code = od_->write(index_, sub_, &f.data[4], len);
    if (code != kSdoOk) return code;
  } else {
    announced_ = indicated ? le32(&f.data[4]) : 0;
    size_indicated_ = indicated;
    if (indicated && (announced_ > capacity || announced_ > kBufferSize)) return kAbortTooLong;
    if (indicated && announced_ < capacity && !is_string) return kAbortTooShort;
    state_ = kDownloading;
    toggle_ = 0;
    length_ = 0;
  }
  respond(sink, 0x60, 0);
  return kSdoOk;
}

SdoAbort SdoServer::download_segment(const CanFrame& f, const CanSink& sink) {
  if (state_ != kDownloading) return kAbortCommand;
  if (!toggle_matches(f.data[0], toggle_)) return kAbortToggle;
  const uint8_t count = segment_size(f.data[0]);
  if (length_ + count > kBufferSize) return kAbortTooLong;
  memcpy(&buffer_[length_], &f.data[1], count);
  length_ = static_cast<uint8_t>(length_ + count);
  const uint8_t ack = static_cast<uint8_t>(0x20 | toggle_);
  toggle_ ^= kSegmentToggle;
  if (segment_last(f.data[0])) {
    // Last segment: the data reaches the OD in one piece or not at all.
    if (size_indicated_ && announced_ != length_) return kAbortTypeMismatch;
    const SdoAbort code = od_->write(index_, sub_, buffer_, length_);
    if (code != kSdoOk) return code;
    state_ = kIdle;
  }
  respond_short(sink, ack);
  return kSdoOk;
}

SdoAbort SdoServer::initiate_upload(const CanSink& sink) {
  uint16_t len = 0;
  // A snapshot: the client reads consistent data even if the value changes.
  const SdoAbort code = od_->read(index_, sub_, buffer_, kBufferSize, &len);
  if (code != kSdoOk) return code;
  if (len >= 1 && len <= 4) {
    // Expedited. Four bytes go without size indication (0x42), as in the
    // frame trace of seed 004 §2.11; shorter values state their size.
    const uint8_t cmd = len == 4 ? 0x42 : expedited_command(0x40, len);
    uint8_t payload[4] = {0, 0, 0, 0};
    memcpy(payload, buffer_, len);
    respond(sink, cmd, le32(payload));
    return kSdoOk;
  }
  length_ = static_cast<uint8_t>(len);
  offset_ = 0;
  toggle_ = 0;
  state_ = kUploading;
  respond(sink, 0x41, len);
  return kSdoOk;
}

SdoAbort SdoServer::upload_segment(const CanFrame& f, const CanSink& sink) {
  if (state_ != kUploading) return kAbortCommand;
  if (!toggle_matches(f.data[0], toggle_)) return kAbortToggle;
  uint8_t count = static_cast<uint8_t>(length_ - offset_);
  if (count > kSegmentBytes) count = kSegmentBytes;
  const bool last = offset_ + count == length_;
  send_sdo(sink, segment_command(toggle_, count, last), &buffer_[offset_], count,
           static_cast<uint16_t>(0x580u + node_id_));
  offset_ = static_cast<uint8_t>(offset_ + count);
  toggle_ ^= kSegmentToggle;
  if (last) state_ = kIdle;
  return kSdoOk;
}

}  // namespace canopen
}  // namespace mb2co
