// SDO server (CiA 301 §7.2.4): expedited and segmented upload and download on
// 600h+id / 580h+id, toggle checking, a server timeout, and an abort with the
// CiA 301 code for every refused request. Block transfer is not offered: its
// command specifiers (5, 6) are answered with 05040001h.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/od.h"

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
  /// Lowers `d` to the server timeout of a transfer in progress.
  void next_deadline(NextDeadline& d) const {
    if (state_ != kIdle) d.at(deadline_us_);
  }
  /// Drops a transfer in progress without a word (NMT stop or reset).
  void cancel() { state_ = kIdle; }
  bool busy() const { return state_ != kIdle; }

 private:
  enum State : uint8_t { kIdle, kDownloading, kUploading };
  void respond(const CanSink& sink, uint8_t cmd, const uint8_t* payload4);
  /// Aborts the transfer of index_/sub_ with `code` and goes idle.
  void abort(const CanSink& sink, SdoAbort code);
  // The request handlers answer themselves and return 0, or return the abort
  // code for on_frame() to send (one abort call site).
  SdoAbort initiate_download(const CanFrame& f, const CanSink& sink);
  SdoAbort download_segment(const CanFrame& f, const CanSink& sink);
  SdoAbort initiate_upload(const CanFrame& f, const CanSink& sink);
  SdoAbort upload_segment(const CanFrame& f, const CanSink& sink);
  /// Takes index and sub-index of a request (bytes 1..3) as index_/sub_.
  void take_multiplexer(const CanFrame& f);

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
};

}  // namespace canopen
}  // namespace mb2co
