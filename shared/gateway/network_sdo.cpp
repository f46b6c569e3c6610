// FC 2Bh / MEI 0Dh service: the SDO client end of a remote transfer
// (CiA 301 §7.2.4.3, expedited and segmented, upload and download), as one
// small state machine keyed on the server's command byte. Its data are the
// Modbus frame's: a download reads the part in the request, an upload
// writes the window into the response being built there. What the master's
// canopen::SdoClient has besides (buffers, streams, capacities, block
// transfer) the gateway never uses; the checks of the server's frames and
// the abort codes are the same.
#include "profiles/profile.h"
#if MB2CO_CONFIG_NETWORK  // else the image leaves the service out (network_slot.h)
#include <string.h>

#include "canopen/sdo_segment.h"
#include "gateway/network_service.h"

namespace mb2co {
namespace gateway {

using namespace canopen;
using modbus::NetMessage;
using modbus::NetService;

void NetworkService::send_mux(uint8_t cmd, uint32_t value) {
  uint8_t bytes[7];
  sdo_mux_bytes(bytes, index_, sub_, value);
  send_sdo(node_.sink(), cmd, bytes, 7, static_cast<uint16_t>(0x600u + server_));
}

void NetworkService::restart_timeout() {
  deadline_us_ = now_us_ + kNetSdoTimeoutUs;
}

void NetworkService::abort(SdoAbort code) {
  send_mux(0x80, code);
  end(code);
}

// A download of 1..4 bytes is one part (a part before the last carries 7
// bytes or more, network_pdu.h): it goes in the initiate. Asked while the
// first part is in hand (start_ 0), whose count tells: the whole object's
// when it is 1..4 bytes.
bool NetworkService::expedited() const {
  return static_cast<uint8_t>(count_ - 1u) < 4u;
}

void NetworkService::start_remote(const NetMessage& m) {
  server_ = m.node_id;
  index_ = m.index;
  sub_ = m.sub;
  pos_ = 0;
  toggle_ = 0;
  restart_timeout();
  if (m.service == NetService::kSdoUpload) {
    phase_ = kUpload;
    step_ = 0x40;
    return send_mux(0x40, 0);
  }
  // The first part of a download (start_ is 0): 1..4 bytes are sent in the
  // initiate, anything else in segments (the size indicated).
  phase_ = kDownload;
  step_ = 0x60;
  size_ = m.object_size;
  if (!expedited()) return send_mux(0x21, size_);
  uint8_t bytes[4] = {0, 0, 0, 0};
  memcpy(bytes, m.data, count_);
  send_mux(expedited_command(0x20, count_), le32(bytes));
}

uint8_t NetworkService::segment_bytes() const {
  const uint8_t left = static_cast<uint8_t>(count_ - sent_);
  return left < kSegmentBytes ? left : kSegmentBytes;
}

// A segment is sent once; if it is lost the server's silence times out.
// Counted in the part in hand (8 bits): its bytes are the request's.
void NetworkService::send_segment(bool in_request) {
  const uint8_t n = segment_bytes();
  const bool last = last_part_;
  // A part before the last all sent: its successor brings the next bytes
  // (an empty last part is an empty object's one segment).
  if (n == 0u && !last) return hold_part();
  // The part's bytes are in the request, in the frame buffer while the
  // request is in hand or its answer pending; gone when the master sent
  // another frame over it.
  if (!in_request && !slave_.answer_pending()) return abort(kAbortGeneral);
  step_ = 0x20;
  send_sdo(node_.sink(), segment_command(toggle_, n, last && sent_ + n == count_),
           slave_.response_pdu() + modbus::net::kSizedHeaderBytes + sent_, n,
           static_cast<uint16_t>(0x600u + server_));
}

// Bytes the response cannot carry (outside the window, or the master gave
// the answer up) are dropped: the transfer runs on to its end.
void NetworkService::store(uint32_t offset, const uint8_t* data, uint8_t n) {
  const uint32_t end = request_end();
  if (!slave_.answer_pending()) return;
  uint8_t* window = slave_.response_pdu() + modbus::net::kSizedHeaderBytes;
  for (; n != 0u && offset < end; --n, ++offset, ++data) {
    if (offset >= start_) window[offset - start_] = *data;
  }
}

SdoAbort NetworkService::on_response(const CanFrame& f) {
  const uint8_t cmd = f.data[0];
  const uint8_t scs = cmd & 0xE0u;
  // The answer the step asks for, and nothing else: a download's initiate
  // answer is 60h exactly.
  if (scs != step_ || (scs == 0x60u && cmd != 0x60u)) return kAbortCommand;
  if ((scs & 0x40u) != 0u) {  // 60h, 40h: an initiate's answer names the object
    if (le16(&f.data[1]) != index_ || f.data[3] != sub_) return kAbortIncompatible;
  } else if (!toggle_matches(cmd, toggle_)) {  // 20h, 00h: a segment's
    return kAbortToggle;
  }
  // Only progress restarts the timeout: every answer taken moves bytes or
  // the protocol on but an empty upload segment that is not the last
  // (00h/10h with n = 7 unused, c = 0), so a server that answers forever
  // with those ends like a silent one (05040000h).
  if ((cmd & 0xEFu) != 0x0Eu) restart_timeout();
  switch (scs) {
    case 0x60:  // download initiated
      if (expedited()) {
        end(kSdoOk);
      } else {
        send_segment(false);
      }
      return kSdoOk;
    case 0x20:  // download segment taken
      sent_ = static_cast<uint8_t>(sent_ + segment_bytes());
      if (sent_ == count_ && last_part_) {
        end(kSdoOk);
        return kSdoOk;
      }
      toggle_ ^= kSegmentToggle;
      send_segment(false);
      return kSdoOk;
    case 0x40: {                  // upload initiated
      if ((cmd & 0x02u) != 0u) {  // expedited: n unused bytes when indicated, else 4 bytes
        const uint8_t n = expedited_size(cmd);
        store(0, &f.data[4], n);
        size_ = n;
        end(kSdoOk);
        return kSdoOk;
      }
      size_known_ = (cmd & 0x01u) != 0u;
      size_ = size_known_ ? le32(&f.data[4]) : 0xFFFFFFFFu;  // unknown: no limit of ours
      break;
    }
    default: {  // 00h: an upload segment
      const uint8_t n = segment_size(cmd);
      // More than announced is the server's error (06070012h); without a
      // size, 32 bits of count are the limit (05040005h).
      const uint32_t pos = pos_ + n;  // what pos_ becomes
      if (n > size_ - pos_) return size_known_ ? kAbortTooLong : kAbortOutOfMemory;
      store(pos_, &f.data[1], n);
      pos_ = pos;
      if (segment_last(cmd)) {
        if (size_known_ && pos != size_) return kAbortTooShort;  // less than announced
        size_ = pos;
        end(kSdoOk);
        return kSdoOk;
      }
      toggle_ ^= kSegmentToggle;
      break;
    }
  }
  // An upload asks for its next segment.
  step_ = 0x00;
  send_sdo(node_.sink(), static_cast<uint8_t>(0x60u | toggle_), nullptr, 0,
           static_cast<uint16_t>(0x600u + server_));
  return kSdoOk;
}

}  // namespace gateway
}  // namespace mb2co
#endif  // MB2CO_CONFIG_NETWORK
