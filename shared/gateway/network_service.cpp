// FC 2Bh / MEI 0Dh service: request dispatch, the local OD for the
// gateway's own node id, remote SDO transfers through the SDO client with
// data in the slave's frame buffer, and multi-part downloads (the client
// waits at the part's end, a segment boundary, until the next part).
#include "profiles/profile.h"
#if MB2CO_CONFIG_NETWORK  // else the image leaves the service out (network_slot.h)
#include <string.h>

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
                               const CanSink& sink, const uint8_t* enabled)
    : NetworkServiceState(),
      node_(node),
      od_(od),
      slave_(slave),
      sink_(sink),
      enabled_(enabled),
      handler_{&NetworkService::handle, this} {}

uint16_t NetworkService::handle(void* ctx, uint8_t* pdu, uint16_t pdu_length, uint16_t capacity) {
  NetworkService& s = *static_cast<NetworkService*>(ctx);
  if (s.enabled_ != nullptr && *s.enabled_ == 0u)
    return modbus::build_net_exception(pdu, Exception::kIllegalFunction);
  NetMessage m{};
  if (!modbus::parse_net_request(pdu, pdu_length, m))
    return modbus::build_net_exception(pdu, Exception::kIllegalDataValue);
  if (s.transfer_running()) return modbus::build_net_exception(pdu, Exception::kServerDeviceBusy);
  const bool next_part = s.phase_ == kDownloadHeld && s.continues_download(m);
  if (s.phase_ == kDownloadHeld && !next_part) s.end_open_download(kAbortGeneral);  // the master moved on
  s.start_ = m.start;
  s.count_ = m.count;
  if (next_part) {
    s.take_part();
    return 0;
  }
  // How an open download ended between parts is news for its next part only.
  const SdoAbort ended = s.phase_ == kDownloadEnded ? s.client_.result() : kSdoOk;
  s.phase_ = kIdle;
  return s.on_request(pdu, capacity, m, ended);
}

uint16_t NetworkService::on_request(uint8_t* pdu, uint16_t capacity, const NetMessage& m, SdoAbort ended) {
  if (m.service == NetService::kNmt) return nmt(pdu, m);
  if (m.service == NetService::kNetworkView) return list_view(pdu, capacity, m.node_id);
  const bool download = m.service == NetService::kSdoDownload;
  SdoAbort code = kSdoOk;
  if (download && m.start != 0u) {
    // A later part with no download open: it continues nothing.
    if (ended == kSdoOk) return modbus::build_net_exception(pdu, Exception::kIllegalDataValue);
    code = ended;
  } else if (m.node_id != node_.node_id()) {
    return start_remote(capacity, m);
  } else if (download) {
    code = local_download(m);
  } else {
    return local_upload(pdu, capacity, m);
  }
  if (code != kSdoOk) return modbus::build_net_abort(pdu, code);
  return modbus::answer_net_request(pdu, false, 0, 0);  // a download's: the request's header and size
}

// ---- immediate services ----------------------------------------------------

uint16_t NetworkService::nmt(uint8_t* pdu, const NetMessage& m) {
  const NmtCommand command = static_cast<NmtCommand>(modbus::net_nmt_command(m));
  const uint8_t target = m.node_id;
  // The response is the request, in place before a reset of our own node.
  const uint16_t length = modbus::answer_net_request(pdu, false, 0, 0);
  if (target != node_.node_id()) {
    // CiA 301 NMT node control: COB-ID 000h, command, node id (0: all).
    const uint8_t frame[2] = {static_cast<uint8_t>(command), target};
    send_frame(sink_, 0x000, 2, frame);
  }
  if (target == 0u || target == node_.node_id()) node_.local_nmt(command, now_us_);
  return length;
}

uint16_t NetworkService::list_view(uint8_t* pdu, uint16_t capacity, uint8_t first) {
  const uint16_t offset = modbus::net::kHeaderBytes;
  const uint16_t room = static_cast<uint16_t>((capacity - offset) / modbus::net::kViewEntryBytes);
  uint16_t count = 0;
  bool more = false;
  for (uint8_t id = first == 0u ? 1u : first; id <= 127u; ++id) {
    modbus::NetViewEntry e = {id, 0, 0};
    if (id == node_.node_id()) {
      e.nmt_state = node_.nmt_state();
    } else {
      const NetworkView::Entry* heard = view_.find(id);
      if (heard == nullptr) continue;
      e.nmt_state = heard->state;
      const uint32_t age_ms = (now_us_ - heard->heard_us) / 1000u;
      e.age_ms =
          age_ms > modbus::net::kAgeSaturated ? modbus::net::kAgeSaturated : static_cast<uint16_t>(age_ms);
    }
    if (count == room) {
      more = true;
      break;
    }
    modbus::put_net_view_entry(pdu + offset + modbus::net::kViewEntryBytes * count, e);
    ++count;
  }
  return modbus::answer_net_request(pdu, more, static_cast<uint16_t>(count * modbus::net::kViewEntryBytes),
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
  if (start_ < size) memmove(pdu + offset, pdu + offset + start_, size - start_);
  set_window(capacity);
  return answer_window(pdu, size);
}

SdoAbort NetworkService::local_download(const NetMessage& m) {
  // No value of the gateway's OD is longer than one frame: one part only.
  if (m.more_follows) return kAbortTooLong;
  return od_.write(m.index, m.sub, m.data, m.count);
}

// ---- remote transfers -------------------------------------------------------

uint16_t NetworkService::start_remote(uint16_t capacity, const NetMessage& m) {
  client_.init(m.node_id);
  client_.set_timeout_us(kNetSdoTimeoutUs);
  const SdoData data = {&NetworkService::data_write, &NetworkService::data_read, this};
  in_request_ = true;
  if (m.service == NetService::kSdoUpload) {
    set_window(capacity);
    phase_ = kUpload;
    client_.start_upload(m.index, m.sub, kSdoAuto, data, 0xFFFFFFFFu, now_us_, sink_);
  } else {
    phase_ = kDownload;  // the first part: start_ is 0
    client_.start_download(m.index, m.sub, m.more_follows ? kSdoSegmented : kSdoAuto, data, m.object_size,
                           now_us_, sink_);
    client_.set_available(count_, sink_);
  }
  in_request_ = false;
  return 0;  // answered when the transfer ends (answer())
}

// The open download's node, object and size are the SDO client's; start_
// and count_ are still the previous part's.
bool NetworkService::continues_download(const NetMessage& m) const {
  return m.service == NetService::kSdoDownload && client_.request_id() == 0x600u + m.node_id &&
         m.index == client_.index() && m.sub == client_.subindex() && m.object_size == client_.size() &&
         m.start == request_end();
}

void NetworkService::take_part() {
  phase_ = kDownload;
  in_request_ = true;  // the client reads the part's first segment now
  client_.set_available(request_end(), sink_);
  in_request_ = false;
}

void NetworkService::end_open_download(SdoAbort code) {
  client_.abort(code, sink_);
  phase_ = kIdle;
}

SdoAbort NetworkService::data_read(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n) {
  NetworkService& s = *static_cast<NetworkService*>(ctx);
  // The part's data are in the request, still in the frame buffer only
  // while the slave holds the answer open (or the request is in hand);
  // gone when the master sent another frame over it. The client reads
  // within [0, request_end()) (set_available) and from where it stopped.
  if (offset < s.start_ || (!s.in_request_ && !s.slave_.answer_pending())) return kAbortGeneral;
  memcpy(buf, s.slave_.response_pdu() + modbus::net::kSizedHeaderBytes + (offset - s.start_), n);
  return kSdoOk;
}

SdoAbort NetworkService::data_write(void* ctx, uint32_t offset, const uint8_t* data, uint16_t n) {
  NetworkService& s = *static_cast<NetworkService*>(ctx);
  if (!s.slave_.answer_pending()) return kSdoOk;  // answer dropped: the transfer runs on, unkept
  uint8_t* window = s.slave_.response_pdu() + modbus::net::kSizedHeaderBytes;
  const uint32_t end = s.request_end();
  for (uint16_t i = 0; i < n; ++i) {
    const uint32_t at = offset + i;
    if (at >= s.start_ && at < end) window[at - s.start_] = data[i];
  }
  return kSdoOk;
}

void NetworkService::answer() {
  const bool part = phase_ == kDownloadHeld;
  const bool upload = phase_ == kUpload;
  if (!part) phase_ = kIdle;
  if (!slave_.answer_pending()) return;  // the master gave it up
  uint8_t* pdu = slave_.response_pdu();
  if (!part && client_.status() == SdoClient::kFailed) {
    slave_.send_deferred(modbus::build_net_abort(pdu, client_.result()));
    return;
  }
  // The request is still in the buffer: the answer is built on it.
  slave_.send_deferred(upload ? answer_window(pdu, client_.size())
                              : modbus::answer_net_request(pdu, false, 0, 0));
}

void NetworkService::set_window(uint16_t capacity) {
  const uint16_t room = static_cast<uint16_t>(capacity - modbus::net::kSizedHeaderBytes);
  if (count_ == 0u || count_ > room) count_ = room;
}

uint16_t NetworkService::answer_window(uint8_t* pdu, uint32_t size) {
  const uint32_t end = min32(request_end(), size);
  const uint16_t count = static_cast<uint16_t>(end > start_ ? end - start_ : 0u);
  return modbus::answer_net_request(pdu, static_cast<uint32_t>(start_) + count < size, count, size);
}

// ---- driving ------------------------------------------------------------------

void NetworkService::on_can_frame(const CanFrame& f, uint32_t now_us) {
  now_us_ = now_us;
  view_.on_frame(f, now_us);
  if (phase_ == kIdle || f.id != client_.response_id()) return;
  client_.on_frame(f, now_us, sink_);
  settle();
}

void NetworkService::process(uint32_t now_us) {
  now_us_ = now_us;
  if (phase_ != kIdle) client_.process(now_us, sink_);
  settle();
}

// A part all sent (the client waits for the next) and a transfer that ended
// are answered; an open download that ended between parts (server abort,
// our timeout) leaves its code for the next part.
void NetworkService::settle() {
  if (phase_ == kDownload && client_.waiting_for_data()) {
    phase_ = kDownloadHeld;
    return answer();
  }
  if (phase_ == kIdle || phase_ == kDownloadEnded || client_.busy()) return;
  if (phase_ == kDownloadHeld) {
    phase_ = kDownloadEnded;  // client_.result() holds the code for the next part
    return;
  }
  answer();
}

void NetworkService::next_deadline(NextDeadline& d) const {
  if (phase_ != kIdle) client_.next_deadline(d);
}

}  // namespace gateway
}  // namespace mb2co
#endif  // MB2CO_CONFIG_NETWORK
