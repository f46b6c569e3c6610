// Modbus/TCP framing (Modbus Messaging on TCP/IP Implementation Guide V1.0b
// §3.1.3), without I/O: the MBAP header in front of a PDU.
//
//   0-1 transaction id (echoed)   2-3 protocol id (0: Modbus)
//   4-5 length: the bytes after it (unit id + PDU, 2..254)
//   6 unit id (echoed)            7.. PDU, function code first, 1..253 bytes
//
// Server side: MbapReceiver collects one request from a byte stream into a
// buffer it owns and frames the response in the same buffer, so that the
// slave builds the response over the request (PduChannel::pdu = pdu()).
// Client side: the master codecs build and check RTU ADUs (address, PDU,
// CRC); mbap_from_rtu() and rtu_from_mbap() carry them over TCP, so one
// codec checks the answers of both transports.
#pragma once
#include <stdint.h>

#include "modbus/protocol.h"
#include "modbus/tcp_channel.h"  // kMaxPduBytes

namespace mb2co {
namespace modbus {

constexpr uint16_t kMbapHeaderBytes = 7;
/// Header and the largest PDU (253 bytes, as on the serial line).
constexpr uint16_t kMaxMbapFrameBytes = kMbapHeaderBytes + kMaxPduBytes;
/// The length field's bounds: unit id + function code .. unit id + 253.
constexpr uint16_t kMinMbapLength = 2;
constexpr uint16_t kMaxMbapLength = kMaxMbapFrameBytes - 6u;
constexpr uint16_t kMbapProtocolModbus = 0;
/// The unit id of a server addressed by its IP address (guide §4.4.1.2).
constexpr uint8_t kMbapUnitDirect = 0xFF;

struct MbapHeader {
  uint16_t transaction;
  uint16_t protocol;
  uint16_t length;  ///< unit id + PDU
  uint8_t unit;
};

MbapHeader read_mbap_header(const uint8_t* p);
void write_mbap_header(uint8_t* p, const MbapHeader& h);

/// The whole frame's length from its header (`p` holds kMbapHeaderBytes);
/// 0 when the length field is outside the bounds (the stream can no
/// longer be cut into frames).
uint16_t mbap_frame_length(const uint8_t* p);

/// One Modbus/TCP request at a time from a byte stream. The caller owns it
/// (one per connection); no heap.
class MbapReceiver {
 public:
  enum class Result : uint8_t {
    kNeedMore,   ///< the frame wants wanted() more bytes
    kRequest,    ///< a whole request: header(), pdu(), pdu_length(); next() when answered
    kForeign,    ///< a whole frame of another protocol id: discarded (guide §4.4.2.2); next()
    kBadLength,  ///< a length field outside 2..254: close the stream (no next frame can be found)
  };

  MbapReceiver() : have_(0), header_() {}

  /// How many more bytes the frame in progress needs (>= 1). A port reads
  /// no more than this, so that what follows stays in the stream.
  uint16_t wanted() const;
  /// Adds `n` (<= wanted()) received bytes.
  Result push(const uint8_t* data, uint16_t n);
  /// Ready for the next frame (after kRequest and its answer, or kForeign).
  void next() { have_ = 0; }

  const MbapHeader& header() const { return header_; }
  uint8_t* pdu() { return buf_ + kMbapHeaderBytes; }
  uint16_t pdu_length() const { return static_cast<uint16_t>(header_.length - 1u); }
  /// Frames the response PDU of `pdu_length` bytes built at pdu(): the
  /// request's transaction and unit id, protocol 0. Returns the frame's
  /// length; the frame starts at frame().
  uint16_t frame_response(uint16_t pdu_length);
  const uint8_t* frame() const { return buf_; }

 private:
  uint8_t buf_[kMaxMbapFrameBytes];
  uint16_t have_;  ///< bytes of the frame in progress in buf_
  MbapHeader header_;
};

/// The MBAP frame of a request ADU as the RTU codecs build it (address,
/// PDU, CRC): unit id = the address, the CRC left off. Returns its length,
/// 0 when `rtu` is shorter than address + function + CRC or the frame
/// does not fit `capacity`.
uint16_t mbap_from_rtu(uint8_t* out, uint16_t capacity, const uint8_t* rtu, uint16_t rtu_length,
                       uint16_t transaction);
/// The RTU ADU of a whole MBAP frame (address = unit id, CRC appended), for
/// the RTU codecs' checks. 0 when `frame` is not one whole frame of
/// protocol 0 or the ADU does not fit `capacity`.
uint16_t rtu_from_mbap(uint8_t* out, uint16_t capacity, const uint8_t* frame, uint16_t frame_length);

}  // namespace modbus
}  // namespace mb2co
