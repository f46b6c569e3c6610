// FC 2Bh / MEI 0Dh service: request dispatch, the local OD for the
// gateway's own node id, remote SDO transfers through the SDO client with
// data in the slave's frame buffer, and multi-part downloads (the client
// waits at the part's end, a segment boundary, until the next part).
#include "profiles/profile.h"
#if MB2CO_CONFIG_NETWORK  // else the image leaves the service out (network_slot.h)
#include "canopen/frame_out.h"
#include "gateway/network_service.h"

namespace mb2co {
namespace gateway {

using namespace canopen;
using modbus::Exception;
using modbus::NetMessage;
using modbus::NetService;

namespace {

uint32_t min32(uint32_t a, uint32_t b) {
  return a < b ? a : b;
}

}  // namespace

NetworkService::NetworkService(Node& node, ObjectDictionary& od, modbus::SlaveCore& slave,
                               const uint32_t& now_us, const uint8_t& enabled)
    : NetworkServiceState(),
      node_(node),
      od_(od),
      slave_(slave),
      now_us_(now_us),
      enabled_(enabled),
      handler_{&NetworkService::handle, this} {}

uint16_t NetworkService::handle(void* ctx, uint8_t* pdu, uint16_t pdu_length, uint16_t capacity) {
  NetworkService& s = *static_cast<NetworkService*>(ctx);
  // A request refused is refused at one place: switched off (2000h/10),
  // malformed, or while a remote transfer runs.
  NetMessage m{};
  const Exception refused = s.enabled_ == 0u                                 ? Exception::kIllegalFunction
                            : !modbus::parse_net_request(pdu, pdu_length, m) ? Exception::kIllegalDataValue
                            : s.transfer_running()                           ? Exception::kServerDeviceBusy
                                                                             : Exception::kNone;
  if (refused != Exception::kNone) return modbus::build_net_exception(pdu, refused);
  const bool next_part = s.phase_ == kDownloadHeld && s.continues_download(m);
  if (s.phase_ == kDownloadHeld && !next_part) {
    s.abort(kAbortGeneral);  // the master moved on
    s.phase_ = kIdle;        // news for nobody: this request is not its part
  }
  s.start_ = m.start;
  s.count_ = static_cast<uint8_t>(m.count);  // a download's, in this frame; an upload's: set_window()
  s.last_part_ = !m.more_follows;
  if (next_part) {
    // The client reads the part's first segment now, from the request.
    s.phase_ = kDownload;
    s.sent_ = 0;
    s.send_segment(true);
    return 0;
  }
  // How an open download ended between parts is news for its next part only.
  const SdoAbort ended = s.phase_ == kDownloadEnded ? s.result_ : kSdoOk;
  s.phase_ = kIdle;
  return s.on_request(pdu, capacity, m, ended);
}

uint16_t NetworkService::on_request(uint8_t* pdu, uint16_t capacity, const NetMessage& m, SdoAbort ended) {
  if (m.service == NetService::kNmt) return nmt(m);
  if (m.service == NetService::kNetworkView) return list_view(pdu, capacity, m.node_id);
  const bool download = m.service == NetService::kSdoDownload;
  if (!download) set_window(capacity, m.count);
  SdoAbort code = kSdoOk;
  if (download && m.start != 0u) {
    // A later part with no download open: it continues nothing.
    if (ended == kSdoOk) return modbus::build_net_exception(pdu, Exception::kIllegalDataValue);
    code = ended;
  } else if (m.node_id != node_.node_id()) {
    start_remote(m);
    return 0;  // answered when the transfer ends (end())
  } else if (download) {
    code = local_download(m);
  } else {
    return local_upload(pdu, capacity, m);
  }
  if (code != kSdoOk) return modbus::build_net_abort(pdu, code);
  return modbus::net::kDownloadAnswerBytes;
}

// ---- immediate services ----------------------------------------------------

uint16_t NetworkService::nmt(const NetMessage& m) {
  const NmtCommand command = static_cast<NmtCommand>(m.data[0]);  // parsed: one byte, a CiA 301 command
  const uint8_t target = m.node_id;
  // The response is the request, as it stands.
  const bool own = target == node_.node_id();
  if (!own) {
    // CiA 301 NMT node control: COB-ID 000h, command, node id (0: all).
    const uint8_t frame[2] = {static_cast<uint8_t>(command), target};
    send_frame(node_.sink(), 0x000, 2, frame);
  }
  if (target == 0u || own) node_.local_nmt(command, now_us_);
  return modbus::net::kNmtAnswerBytes;
}

uint16_t NetworkService::list_view(uint8_t* pdu, uint16_t capacity, uint8_t first) {
  // Entries are written from the header on while a whole one fits.
  uint8_t* entry = pdu + modbus::net::kHeaderBytes;
  const uint8_t* const last = pdu + capacity - modbus::net::kViewEntryBytes;
  bool more = false;
  const uint32_t now_us = now_us_;  // read once: the entries written may alias it
  for (uint8_t id = first == 0u ? 1u : first; id <= 127u; ++id) {
    modbus::NetViewEntry e = {id, 0, 0};
    if (id == node_.node_id()) {
      e.nmt_state = node_.nmt_state();
    } else {
      const NetworkView::Entry* heard = view_.find(id);
      if (heard == nullptr) continue;
      e.nmt_state = heard->state;
      const uint32_t age_ms = (now_us - heard->heard_us) / 1000u;
      e.age_ms =
          age_ms > modbus::net::kAgeSaturated ? modbus::net::kAgeSaturated : static_cast<uint16_t>(age_ms);
    }
    if (entry > last) {
      more = true;
      break;
    }
    modbus::put_net_view_entry(entry, e);
    entry += modbus::net::kViewEntryBytes;
  }
  return modbus::answer_net_request(pdu, more, static_cast<uint16_t>(entry - pdu - modbus::net::kHeaderBytes),
                                    0);
}

// The gateway's own node: the local OD, as its SDO server would answer.
// The upload's bytes go where the response carries them (the tail from the
// starting address: at least the window, within the buffer).
uint16_t NetworkService::local_upload(uint8_t* pdu, uint16_t capacity, const NetMessage& m) {
  const uint16_t offset = modbus::net::kSizedHeaderBytes;
  uint16_t size = 0;
  const SdoAbort code =
      od_.read(m.index, m.sub, pdu + offset, static_cast<uint16_t>(capacity - offset), &size);
  if (code != kSdoOk) return modbus::build_net_abort(pdu, code);
  // Forward, byte by byte (no copy routine only this would link): a byte
  // never lands after its source; none when the window starts beyond the
  // object (a pointer that far would wrap on the Uno).
  uint8_t* to = pdu + offset;
  const uint8_t* const end = to + size;
  if (start_ < size) {
    for (const uint8_t* from = to + start_; from != end; ++from, ++to) *to = *from;
  }
  size_ = size;  // no transfer runs: the answer's object size
  return answer_window(pdu);
}

SdoAbort NetworkService::local_download(const NetMessage& m) {
  // No value of the gateway's OD is longer than one frame: one part only.
  if (m.more_follows) return kAbortTooLong;
  return od_.write(m.index, m.sub, m.data, m.count);
}

// ---- remote transfers (the SDO client end: network_sdo.cpp) ----------------

// The open download's node, object and size are the transfer's; start_
// and count_ are still the previous part's.
bool NetworkService::continues_download(const NetMessage& m) const {
  return m.service == NetService::kSdoDownload && m.node_id == server_ && m.index == index_ &&
         m.sub == sub_ && m.object_size == size_ && m.start == request_end();
}

void NetworkService::hold_part() {
  phase_ = kDownloadHeld;
  step_ = kStepNone;  // any frame of the server's now is out of place
  // The part's answer: the request's header and size, still in the buffer.
  slave_.send_deferred(modbus::net::kDownloadAnswerBytes);
}

// An open download that ended between parts leaves its code for the next
// part; a transfer in hand is answered (unless the master gave it up).
void NetworkService::end(SdoAbort code) {
  result_ = code;
  if (phase_ == kDownloadHeld) {
    phase_ = kDownloadEnded;
    return;
  }
  const bool upload = phase_ == kUpload;
  phase_ = kIdle;
  if (!slave_.answer_pending()) return;
  uint8_t* pdu = slave_.response_pdu();
  // The request is still in the buffer: the answer is built on it.
  slave_.send_deferred(code != kSdoOk ? modbus::build_net_abort(pdu, code)
                       : upload       ? answer_window(pdu)
                                      : modbus::net::kDownloadAnswerBytes);
}

void NetworkService::set_window(uint16_t capacity, uint16_t wanted) {
  const uint16_t room = static_cast<uint16_t>(capacity - modbus::net::kSizedHeaderBytes);
  count_ = static_cast<uint8_t>(wanted == 0u || wanted > room ? room : wanted);  // room <= kMaxSdoData
}

uint16_t NetworkService::answer_window(uint8_t* pdu) {
  const uint32_t size = size_;
  const uint32_t end = min32(request_end(), size);
  const uint16_t count = static_cast<uint16_t>(end > start_ ? end - start_ : 0u);
  return modbus::answer_net_request(pdu, static_cast<uint32_t>(start_) + count < size, count, size);
}

// ---- driving ------------------------------------------------------------------

void NetworkService::on_can_frame(const CanFrame& f, uint32_t now_us) {
  // Heartbeats and SDO responses are standard data frames: an RTR (a
  // guarding request on 700h + n) or an extended frame is neither.
  if (f.flags != 0u) return;
  // The server's response (580h + n) is no heartbeat (700h + n): one or
  // the other.
  if (phase_ < kUpload || f.id != 0x580u + server_ || f.dlc != 8u) return view_.on_frame(f, now_us);
  // 80h is the server's abort in every step.
  if (f.data[0] == 0x80u) return end(static_cast<SdoAbort>(le32(&f.data[4])));
  const SdoAbort code = on_response(f);
  if (code != kSdoOk) abort(code);
}

void NetworkService::process(uint32_t now_us) {
  if (phase_ >= kUpload && time_reached(now_us, deadline_us_)) abort(kAbortTimeout);
}

void NetworkService::next_deadline(NextDeadline& d) const {
  if (phase_ >= kUpload) d.at(deadline_us_);
}

}  // namespace gateway
}  // namespace mb2co
#endif  // MB2CO_CONFIG_NETWORK
