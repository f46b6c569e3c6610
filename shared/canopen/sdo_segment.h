// The expedited and segmented SDO protocol (CiA 301 §7.2.4.3.3-8) as both
// ends speak it: the SdoServer and the SdoClient build and read their frames
// with this one piece, so an image with both (the Uno's network gateway)
// carries the frame code once.
//
// Frame layout (byte 0; bytes 1..3 index and sub-index where named):
//   initiate  download  C: 001 0 n(2) e s, mux, data or size   S: 011 00000, mux
//             upload    C: 010 00000, mux    S: 010 0 n(2) e s, mux, data or size
//   segment   download  C: 000 t n(3) c, 7 bytes               S: 001 t 0000
//             upload    C: 011 t 0000        S: 000 t n(3) c, 7 bytes
//   abort               either: 100 00000, mux, abort code (little-endian)
// e: expedited; s: size indicated; n: bytes of the frame that carry no data;
// c: last segment; t: the toggle bit, 0 in the first segment, alternating.
// A segment carries the same bytes in both directions and its answer echoes
// its toggle. Each end keeps its own count of the bytes moved: the server's
// values fit its 32-byte buffer and 8-bit counts, the client's objects need
// 32 bits, and one 32-bit segment machine for both ends made the Uno's
// server larger than the two apart (docs/performance.md). What is shared is
// every bit of the frames: the codes below and the one frame builder.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"

namespace mb2co {
namespace canopen {

/// Data bytes in one segment.
constexpr uint8_t kSegmentBytes = 7;
/// The toggle bit of byte 0 of a segment and of its answer.
constexpr uint8_t kSegmentToggle = 0x10;

/// Data bytes of an expedited initiate with command byte `cmd`: 4 - n when
/// the size is indicated (s = 1), else all 4.
inline uint8_t expedited_size(uint8_t cmd) {
  return (cmd & 0x01) != 0 ? static_cast<uint8_t>(4 - ((cmd >> 2) & 0x03)) : static_cast<uint8_t>(4);
}

/// Command byte of an expedited initiate carrying `n` (1..4) bytes, size
/// indicated; `base` is 20h (download request) or 40h (upload response).
inline uint8_t expedited_command(uint8_t base, uint32_t n) {
  return static_cast<uint8_t>(base | 0x03 | ((4 - n) << 2));
}

/// Byte 0 of a segment (download request, upload response) carrying `n`
/// (0..7) data bytes with toggle bit `toggle`; `last`: c = 1.
inline uint8_t segment_command(uint8_t toggle, uint8_t n, bool last) {
  return static_cast<uint8_t>(toggle | ((kSegmentBytes - n) << 1) | (last ? 1 : 0));
}

/// Data bytes of a segment with byte 0 `cmd` (7 - n).
inline uint8_t segment_size(uint8_t cmd) {
  return static_cast<uint8_t>(kSegmentBytes - ((cmd >> 1) & 0x07));
}

/// True when segment byte 0 `cmd` has c = 1 (no segment follows).
inline bool segment_last(uint8_t cmd) {
  return (cmd & 0x01) != 0;
}

/// True when byte 0 `cmd` of a segment or of its answer carries the toggle
/// bit `toggle` (0 or kSegmentToggle) the other end expects.
inline bool toggle_matches(uint8_t cmd, uint8_t toggle) {
  return (cmd & kSegmentToggle) == toggle;
}

/// Sends an SDO frame: byte 0 `cmd`, then `n` (0..7) bytes of `bytes`, the
/// rest 0 (CiA 301 sends reserved bytes as 0), on `cob_id`: a segment, a
/// segment's answer or request (n = 0), an initiate or abort frame (n = 7:
/// the multiplexer and 4 bytes, sdo_mux_bytes()).
void send_sdo(const CanSink& sink, uint8_t cmd, const uint8_t* bytes, uint8_t n, uint16_t cob_id);

/// Bytes 1..7 of an initiate or abort frame into `out`: the multiplexer
/// (`index`, `sub`) and `value` as 4 little-endian bytes (data, a size, an
/// abort code).
void sdo_mux_bytes(uint8_t* out, uint16_t index, uint8_t sub, uint32_t value);

}  // namespace canopen
}  // namespace mb2co
