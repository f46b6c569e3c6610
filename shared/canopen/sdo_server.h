// SDO server (CiA 301 §7.2.4): expedited and segmented upload and download on
// 600h+id / 580h+id, toggle checking, a server timeout, and an abort with the
// CiA 301 code for every refused request.
//
// MB2CO_CONFIG_SDO_BLOCK (defined for host builds by shared/canopen/CMakeLists.txt,
// never for the AVR images, which must not grow) adds block upload and
// download (sdo_block_server.cpp: CRC, sub-blocks resent from the client's
// ackseq, the end phase, the protocol switch; on with set_block_transfer)
// and application objects outside the OD (set_domain, sdo_domain.h), moved
// by every kind of transfer. Without it, or while it is off, block requests
// (command specifiers 5, 6) are answered with 05040001h.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/od.h"
#include "canopen/sdo_segment.h"
#include "profiles/profile.h"
#if MB2CO_CONFIG_SDO_BLOCK
#include "canopen/sdo_block.h"
#include "canopen/sdo_domain.h"
#endif

namespace mb2co {
namespace canopen {

/// Members that start at zero have no initialisers: the owner (NodeState)
/// is value-initialised, which zero-fills it in one go.
class SdoServer {
 public:
  /// Largest object moved by a segmented transfer (strings); bigger → 06070012h.
  static const uint8_t kBufferSize = 32;
  /// Default server timeout between segments (CiA 301 leaves it to the device).
  static const uint32_t kDefaultTimeoutUs = 1000000u;

  void init(ObjectDictionary* od, uint8_t node_id);
  void set_timeout_us(uint32_t us) { timeout_us_ = us; }
  /// A frame on 600h+id. Frames that are not 8 bytes long and RTR frames are
  /// ignored (CiA 301: SDO frames have 8 bytes; there is nobody to answer).
  void on_frame(const CanFrame& f, uint32_t now_us, const CanSink& sink);
  /// Aborts a segmented transfer whose client went silent (05040000h).
  void process(uint32_t now_us, const CanSink& sink);
  /// Lowers `d` to the server timeout of a transfer in progress (now when
  /// block segments wait for room in the transmit queue).
  void next_deadline(NextDeadline& d) const {
    if (state_ != kIdle) d.at(deadline_us_);
    if (sending()) d.now();
  }
  /// Drops a transfer in progress without a word (NMT stop or reset).
  void cancel() { state_ = kIdle; }
  bool busy() const { return state_ != kIdle; }
#if MB2CO_CONFIG_SDO_BLOCK
  /// Objects served outside the OD, asked before it (null: none). Must
  /// outlive the server; init() keeps it.
  void set_domain(const SdoDomain* domain) {
    domain_ = domain;
  }
  /// Block transfer on or off. Off by default: block requests are answered
  /// with 05040001h as by the AVR images, so a host model of an Uno (the
  /// simulator, the tests of its behaviour) stays faithful; an application
  /// that offers block transfer (mb2co-node) turns it on.
  void set_block_transfer(bool on) {
    block_ = on;
  }
  /// Sub-block size we ask for as the receiver of a block download (1..127).
  void set_block_size(uint8_t blksize) {
    block_size_ = blksize;
  }

 private:
  /// True while block segments wait for room in the transmit queue.
  bool sending() const {
    return state_ == kBlockUploadSub && sender_.pending();
  }
#else

 private:
  bool sending() const {
    return false;
  }
#endif

  enum State : uint8_t {
    kIdle,
    kDownloading,
    kUploading,
#if MB2CO_CONFIG_SDO_BLOCK
    kDomainDownloading,  ///< segmented download into domain_
    kDomainUploading,    ///< segmented upload from domain_
    kBlockDownloadSub,   ///< takes the segments of sub-blocks
    kBlockDownloadEnd,   ///< waits for the end request
    kBlockUploadStart,   ///< waits for the client's start (A3h)
    kBlockUploadSub,     ///< sends a sub-block, waits for its ack
    kBlockUploadEnd,     ///< sent the end frame, waits for A1h
#endif
  };
  /// Sends `cmd`, the multiplexer index_/sub_ and `value` (send_sdo_mux).
  void respond(const CanSink& sink, uint8_t cmd, uint32_t value);
  /// Sends `cmd` with bytes 1..7 reserved (0): a segment's answer.
  void respond_short(const CanSink& sink, uint8_t cmd);
  /// Aborts the transfer of index_/sub_ with `code` and goes idle.
  void abort(const CanSink& sink, SdoAbort code);
  // The request handlers answer themselves and return 0, or return the abort
  // code for on_frame() to send (one abort call site).
  SdoAbort initiate_download(const CanFrame& f, const CanSink& sink);
  SdoAbort download_segment(const CanFrame& f, const CanSink& sink);
  SdoAbort initiate_upload(const CanSink& sink);
  SdoAbort upload_segment(const CanFrame& f, const CanSink& sink);
  /// Takes index and sub-index of a request (bytes 1..3) as index_/sub_.
  void take_multiplexer(const CanFrame& f);
#if MB2CO_CONFIG_SDO_BLOCK
  // sdo_block_server.cpp. True when the frame was one of the host-only
  // kinds (block, domain) and *code says how it ended.
  bool on_host_frame(const CanFrame& f, const CanSink& sink, SdoAbort* code);
  bool domain_owns(const CanFrame& f) const;
  SdoAbort domain_download(const CanFrame& f, const CanSink& sink);
  SdoAbort domain_download_segment(const CanFrame& f, const CanSink& sink);
  SdoAbort domain_upload(const CanFrame& f, const CanSink& sink);
  SdoAbort domain_upload_segment(const CanFrame& f, const CanSink& sink);
  SdoAbort block_download(const CanFrame& f, const CanSink& sink);
  SdoAbort block_download_segment(const CanFrame& f, const CanSink& sink);
  SdoAbort block_upload(const CanFrame& f, const CanSink& sink);
  SdoAbort pump(const CanSink& sink);
  void process_block(const CanSink& sink);
  /// The object of index_/sub_ as a byte stream: domain_ or buffer_.
  SdoData stream();
  static SdoAbort buffer_write(void* ctx, uint32_t offset, const uint8_t* data, uint16_t n);
  static SdoAbort buffer_read(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n);
  static SdoAbort domain_write(void* ctx, uint32_t offset, const uint8_t* data, uint16_t n);
  static SdoAbort domain_read(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n);
#endif

  ObjectDictionary* od_;
  uint32_t timeout_us_ = kDefaultTimeoutUs;
  uint32_t deadline_us_;
  uint32_t announced_;  ///< size from the initiate request (0: not indicated)
  uint16_t index_;
  uint8_t sub_;
  uint8_t node_id_;
  State state_;
  uint8_t toggle_;  ///< expected toggle bit (0x00 or 0x10)
  uint8_t length_;  ///< bytes in buffer_
  uint8_t offset_;  ///< upload: bytes already sent
  bool size_indicated_;
  uint8_t buffer_[kBufferSize];
#if MB2CO_CONFIG_SDO_BLOCK
  const SdoDomain* domain_;
  BlockSender sender_;
  BlockReceiver receiver_;
  uint32_t pos_;   ///< domain transfers: bytes moved
  uint32_t size_;  ///< domain upload: its size
  uint8_t block_size_ = kBlockSizeMax;
  bool in_domain_;  ///< the transfer's object is domain_'s, not the OD's
  bool crc_;        ///< block transfer: both ends check the CRC
  bool block_;      ///< block transfer offered (set_block_transfer)
#endif
};

}  // namespace canopen
}  // namespace mb2co
