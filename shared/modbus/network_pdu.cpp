// FC 2Bh / MEI 0Dh codec: one layout function per direction, the checks of
// each service in one place (see network_pdu.h and docs/gateway-network.md).
#include "modbus/network_pdu.h"

#include <string.h>

#include "crc/crc16.h"
#include "modbus/master_codec.h"

namespace mb2co {
namespace modbus {
namespace {

// Protocol control bits 7-5 of each service: its NetService value.
uint8_t service_bits(NetService s) {
  return static_cast<uint8_t>(static_cast<uint8_t>(s) << 5);
}

// The service of protocol control byte `control`: bits 7-5 are 000, 001,
// 011 or 100 (NetService's values), else none.
bool service_of(uint8_t control, NetService& out) {
  const uint8_t bits = static_cast<uint8_t>(control >> 5);
  out = static_cast<NetService>(bits);
  return bits <= 4u && bits != 2u;
}

uint32_t get_be32(const uint8_t* p) {
  return (static_cast<uint32_t>(get_be16(p)) << 16) | get_be16(p + 2);
}

void put_be32(uint8_t* p, uint32_t v) {
  put_be16(p, static_cast<uint16_t>(v >> 16));
  put_be16(p + 2, static_cast<uint16_t>(v & 0xFFFFu));
}

bool valid_nmt_command(uint8_t cs) {
  return cs == 0x01 || cs == 0x02 || cs == 0x80 || cs == 0x81 || cs == 0x82;
}

// Which optional parts a message of `service` carries in each direction.
struct Shape {
  bool sized;  ///< the 4-byte object size after the header
  bool data;   ///< data bytes after the header (and size)
};

// A request carries data when it writes (access bit 5: download, NMT), the
// object size when it is a download.
Shape request_shape(NetService s) {
  return Shape{s == NetService::kSdoDownload, (static_cast<uint8_t>(s) & 0x01u) != 0u};
}

// Every SDO response carries the object size; every response but a
// download's carries data.
Shape response_shape(NetService s) {
  return Shape{s == NetService::kSdoUpload || s == NetService::kSdoDownload, s != NetService::kSdoDownload};
}

// Header fields shared by requests and responses.
void decode_header(const uint8_t* p, NetMessage& m) {
  m.more_follows = (p[2] & net::kMoreFollows) != 0u;
  m.node_id = p[4];
  m.index = get_be16(p + 5);
  m.sub = p[7];
  m.start = get_be16(p + 8);
  m.count = get_be16(p + 10);
}

// Writes `m` in `shape`; the data come from m.data (data_length bytes; may
// already be in place). Returns the PDU length, 0 when it does not fit.
uint16_t encode(uint8_t* p, uint16_t capacity, const NetMessage& m, Shape shape) {
  const uint16_t offset = shape.sized ? net::kSizedHeaderBytes : net::kHeaderBytes;
  const uint16_t data_length = shape.data ? m.data_length : 0u;
  if (capacity < offset || data_length > capacity - offset) return 0;
  if (data_length != 0u) memmove(p + offset, m.data, data_length);
  p[0] = fc::kEncapsulatedInterface;
  p[1] = kMeiCanopenReference;
  p[2] = static_cast<uint8_t>(service_bits(m.service) | (m.more_follows ? net::kMoreFollows : 0u));
  p[3] = 0;
  p[4] = m.node_id;
  put_be16(p + 5, m.index);
  p[7] = m.sub;
  put_be16(p + 8, m.start);
  put_be16(p + 10, m.count);
  if (shape.sized) put_be32(p + 12, m.object_size);
  return static_cast<uint16_t>(offset + data_length);
}

bool parse_sdo_download(const uint8_t* p, uint16_t length, NetMessage& m) {
  if (length < net::kSizedHeaderBytes) return false;
  m.object_size = get_be32(p + 12);
  m.data = p + net::kSizedHeaderBytes;
  m.data_length = static_cast<uint16_t>(length - net::kSizedHeaderBytes);
  if (m.count != m.data_length) return false;
  const uint32_t end = static_cast<uint32_t>(m.start) + m.count;
  if (end > m.object_size) return false;
  // The last part ends the object; a part before it ends before the object
  // and carries whole segments.
  if ((end == m.object_size) == m.more_follows) return false;
  return !m.more_follows || (m.count != 0u && m.count % net::kPartMultiple == 0u);
}

}  // namespace

bool parse_net_request(const uint8_t* pdu, uint16_t pdu_length, NetMessage& out) {
  out = NetMessage{};
  if (pdu_length < net::kHeaderBytes) return false;
  if ((pdu[2] & net::kReservedControlBits) != 0u || pdu[3] != 0u) return false;
  if (!service_of(pdu[2], out.service)) return false;
  decode_header(pdu, out);
  const bool sdo = out.service <= NetService::kSdoDownload;
  // Every service: a node id up to 127 (an SDO transfer's a node's, not 0);
  // more follows only on a download.
  if (out.node_id > 127u || (sdo && out.node_id == 0u) ||
      (out.more_follows && out.service != NetService::kSdoDownload)) {
    return false;
  }
  if (out.service == NetService::kSdoDownload) return parse_sdo_download(pdu, pdu_length, out);
  // The rest have a fixed length: the header, and NMT's command byte.
  const uint8_t body = out.service == NetService::kNmt ? 1u : 0u;
  if (pdu_length != net::kHeaderBytes + body) return false;
  if (sdo) return out.count <= 0xFFFFu - out.start;  // an upload's window ends within 16 bits
  // NMT and the network view use no index, subindex or starting address,
  // and count their data: NMT one byte, a command CiA 301 defines.
  if ((out.index | out.sub | out.start) != 0u || out.count != body) return false;
  if (body == 0u) return true;
  out.data = pdu + net::kHeaderBytes;
  out.data_length = 1;
  return valid_nmt_command(out.data[0]);
}

uint16_t build_net_response(uint8_t* pdu, uint16_t capacity, const NetMessage& m) {
  return encode(pdu, capacity, m, response_shape(m.service));
}

uint16_t net_response_data_offset(NetService service) {
  return response_shape(service).sized ? net::kSizedHeaderBytes : net::kHeaderBytes;
}

uint16_t answer_net_request(uint8_t* pdu, bool more, uint16_t count, uint32_t size) {
  // Parsed: an upload (bits 7-5 000) or a view request, more follows 0.
  if (more) pdu[2] = static_cast<uint8_t>(pdu[2] | net::kMoreFollows);
  put_be16(pdu + 10, count);
  if (pdu[2] >= service_bits(NetService::kNetworkView))
    return static_cast<uint16_t>(net::kHeaderBytes + count);
  put_be32(pdu + 12, size);
  return static_cast<uint16_t>(net::kSizedHeaderBytes + count);
}

uint16_t build_net_exception(uint8_t* pdu, Exception code) {
  pdu[0] = static_cast<uint8_t>(fc::kEncapsulatedInterface | fc::kExceptionFlag);
  pdu[1] = static_cast<uint8_t>(code);
  return 2;
}

uint16_t build_net_abort(uint8_t* pdu, uint32_t abort_code) {
  build_net_exception(pdu, Exception::kServerDeviceFailure);
  pdu[2] = kMeiCanopenReference;
  put_be32(pdu + 3, abort_code);
  return net::kAbortExceptionBytes;
}

void put_net_view_entry(uint8_t* p, const NetViewEntry& e) {
  p[0] = e.node_id;
  p[1] = e.nmt_state;
  put_be16(p + 2, e.age_ms);
}

NetViewEntry net_view_entry(const NetMessage& m, uint16_t i) {
  const uint8_t* p = m.data + net::kViewEntryBytes * i;
  return NetViewEntry{p[0], p[1], get_be16(p + 2)};
}

// ---- master side ------------------------------------------------------------

uint16_t build_net_request(uint8_t* out, uint16_t capacity, uint8_t address, const NetMessage& m) {
  if (capacity < 1u + kCrcBytes) return 0;
  const uint16_t pdu_length =
      encode(out + 1, static_cast<uint16_t>(capacity - 1u - kCrcBytes), m, request_shape(m.service));
  if (pdu_length == 0u) return 0;
  out[0] = address;
  return append_crc(out, static_cast<uint16_t>(pdu_length + 1u));
}

uint16_t build_net_upload(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t node_id, uint16_t index,
                          uint8_t sub, uint16_t start, uint16_t max_count) {
  NetMessage m{};
  m.service = NetService::kSdoUpload;
  m.node_id = node_id;
  m.index = index;
  m.sub = sub;
  m.start = start;
  m.count = max_count;
  return build_net_request(out, capacity, address, m);
}

uint16_t build_net_download(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t node_id, uint16_t index,
                            uint8_t sub, uint32_t object_size, uint16_t start, const uint8_t* data,
                            uint16_t count, bool more) {
  NetMessage m{};
  m.service = NetService::kSdoDownload;
  m.more_follows = more;
  m.node_id = node_id;
  m.index = index;
  m.sub = sub;
  m.start = start;
  m.count = count;
  m.object_size = object_size;
  m.data = data;
  m.data_length = count;
  return build_net_request(out, capacity, address, m);
}

uint16_t build_net_nmt(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t node_id, uint8_t command) {
  NetMessage m{};
  m.service = NetService::kNmt;
  m.node_id = node_id;
  m.count = 1;
  m.data = &command;
  m.data_length = 1;
  return build_net_request(out, capacity, address, m);
}

uint16_t build_net_view(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t first_node_id) {
  NetMessage m{};
  m.service = NetService::kNetworkView;
  m.node_id = first_node_id;
  return build_net_request(out, capacity, address, m);
}

namespace {

ParseStatus check_body(const uint8_t* q, const uint8_t* p, uint16_t pdu_length, NetMessage& m) {
  if (pdu_length < net::kHeaderBytes) return ParseStatus::kBadLength;
  if (p[1] != kMeiCanopenReference || p[3] != 0u) return ParseStatus::kMismatch;
  if (!service_of(p[2], m.service) || (p[2] & 0xE0u) != (q[2] & 0xE0u)) return ParseStatus::kMismatch;
  if (memcmp(p + 4, q + 4, 6) != 0) return ParseStatus::kMismatch;  // node, index, sub, start
  decode_header(p, m);
  const Shape shape = response_shape(m.service);
  const uint16_t offset = shape.sized ? net::kSizedHeaderBytes : net::kHeaderBytes;
  if (pdu_length < offset) return ParseStatus::kBadLength;
  if (shape.sized) m.object_size = get_be32(p + 12);
  m.data = p + offset;
  m.data_length = static_cast<uint16_t>(pdu_length - offset);
  switch (m.service) {
    case NetService::kSdoUpload:
      if (m.count != m.data_length) return ParseStatus::kBadLength;
      // A window beyond the object's end comes back empty.
      if (m.count != 0u && static_cast<uint32_t>(m.start) + m.count > m.object_size)
        return ParseStatus::kBadLength;
      return ParseStatus::kOk;
    case NetService::kSdoDownload:
      if (m.data_length != 0u) return ParseStatus::kBadLength;
      return m.count == get_be16(q + 10) ? ParseStatus::kOk : ParseStatus::kMismatch;
    case NetService::kNmt:
      if (m.data_length != 1u || m.count != 1u) return ParseStatus::kBadLength;
      return p[12] == q[12] ? ParseStatus::kOk : ParseStatus::kMismatch;
    case NetService::kNetworkView:
    default:
      if (m.count != m.data_length || m.count % net::kViewEntryBytes != 0u) return ParseStatus::kBadLength;
      return ParseStatus::kOk;
  }
}

}  // namespace

ParseStatus parse_net_response(const uint8_t* request, uint16_t request_length, const uint8_t* response,
                               uint16_t response_length, NetResponse& out) {
  out = NetResponse{};
  if (request_length < 1u + net::kHeaderBytes + kCrcBytes || !is_net_pdu(request + 1, net::kHeaderBytes)) {
    return ParseStatus::kBadRequest;
  }
  if (response_length < 5u) return ParseStatus::kTooShort;
  if (!crc_ok(response, response_length)) return ParseStatus::kBadCrc;
  if (response[0] != request[0]) return ParseStatus::kWrongAddress;
  const uint8_t* q = request + 1;
  const uint8_t* p = response + 1;
  const uint16_t pdu_length = static_cast<uint16_t>(response_length - 1u - kCrcBytes);
  if (p[0] == (fc::kEncapsulatedInterface | fc::kExceptionFlag)) {
    out.exception = static_cast<Exception>(p[1]);
    if (pdu_length == 2u) return ParseStatus::kException;
    if (pdu_length != net::kAbortExceptionBytes || out.exception != Exception::kServerDeviceFailure ||
        p[2] != kMeiCanopenReference) {
      return ParseStatus::kBadLength;
    }
    out.abort_code = get_be32(p + 3);
    return ParseStatus::kException;
  }
  if (p[0] != fc::kEncapsulatedInterface) return ParseStatus::kWrongFunction;
  return check_body(q, p, pdu_length, out.message);
}

}  // namespace modbus
}  // namespace mb2co
