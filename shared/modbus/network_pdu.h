// FC 2Bh / MEI 0Dh, "CANopen General Reference" (Modbus application protocol
// §6.20; the service set of CiA 309-2): the PDU codec, without I/O. The slave
// side parses a request and builds the response in place; the master side
// builds a request ADU and checks the response against it. The byte-by-byte
// layout, the exceptions and the timing are documented in
// docs/gateway-network.md; the offsets below are PDU offsets (function code
// at 0).
//
//   0 2Bh   1 0Dh   2 protocol control   3 reserved (0)   4 node id
//   5-6 index (big-endian)   7 subindex   8-9 starting address (big-endian)
//   10-11 number of data (big-endian)
//   12-15 object size (big-endian): SDO download request, SDO responses
//   then the data, `number of data` bytes (object bytes in CANopen order)
//
// Protocol control: bit 0 more follows, bit 5 access (1 write), bits 6-7 the
// service (0 SDO, 1 NMT, 2 network view), bits 1-4 reserved (0).
// Exception 04 with an SDO abort is the one longer exception response:
// AB 04 0D followed by the 32-bit abort code, big-endian.
#pragma once
#include <stdint.h>

#include "modbus/protocol.h"

namespace mb2co {
namespace modbus {

/// Defined in modbus/master_codec.h (include it to use parse_net_response);
/// not included here: the Arduino core's bit() macro clashes with it, and the
/// Uno's sketch sees this header through the gateway.
enum class ParseStatus : uint8_t;

namespace net {
/// Protocol control bits (PDU byte 2).
constexpr uint8_t kMoreFollows = 0x01;
constexpr uint8_t kWriteAccess = 0x20;
constexpr uint8_t kServiceShift = 6;
constexpr uint8_t kReservedControlBits = 0x1E;

/// Fixed part of every request and normal response: FC .. number of data.
constexpr uint16_t kHeaderBytes = 12;
/// Header plus the 4-byte object size of the SDO messages that carry one.
constexpr uint16_t kSizedHeaderBytes = 16;
/// Largest PDU of an RTU frame (256-byte ADU).
constexpr uint16_t kMaxPduBytes = kMaxAduBytes - 1u - kCrcBytes;
/// Most object bytes one upload response or download request carries.
constexpr uint16_t kMaxSdoData = kMaxPduBytes - kSizedHeaderBytes;  // 237
/// A download part before the last carries whole SDO segments: a multiple
/// of this many bytes (the gateway's client waits between parts at a
/// segment boundary and keeps no bytes over).
constexpr uint16_t kPartMultiple = 7;
/// Most bytes of a download part before the last.
constexpr uint16_t kMaxPartBytes = kMaxSdoData / kPartMultiple * kPartMultiple;  // 231
/// One network view entry: node id, NMT state, heartbeat age ms (BE 16).
constexpr uint16_t kViewEntryBytes = 4;
/// Most view entries in one response.
constexpr uint16_t kMaxViewEntries = (kMaxPduBytes - kHeaderBytes) / kViewEntryBytes;  // 60
/// The normal response to a download part: the request's header and object
/// size as they stand (the data dropped).
constexpr uint16_t kDownloadAnswerBytes = kSizedHeaderBytes;
/// The normal response to an NMT request: the request itself.
constexpr uint16_t kNmtAnswerBytes = kHeaderBytes + 1u;
/// The exception response carrying an SDO abort: AB 04 0D + 4 bytes.
constexpr uint16_t kAbortExceptionBytes = 7;
/// Heartbeat age when it does not fit 16 bits (65.535 s or more).
constexpr uint16_t kAgeSaturated = 0xFFFF;
/// NMT state byte of a view entry that has heard nothing yet.
constexpr uint8_t kStateUnknown = 0xFF;
}  // namespace net

/// The services; each value is its wire form, protocol control bits 7-5
/// (service bits 7-6, access bit 5).
enum class NetService : uint8_t {
  kSdoUpload = 0,    ///< SDO, read: bits 7-5 = 000
  kSdoDownload = 1,  ///< SDO, write: 001
  kNmt = 3,          ///< NMT command, write: 011
  kNetworkView = 4,  ///< network view, read: 100
};

/// One request or normal response, decoded. `data` points into the PDU it
/// was parsed from (valid while that buffer is), or at what a builder copies.
/// Plain data without initialisers (the Uno's gateway holds one in a
/// zero-filled block): declare it value-initialised, `NetMessage m{};`.
struct NetMessage {
  NetService service;
  bool more_follows;
  uint8_t node_id;       ///< SDO 1..127; NMT 0 (all) ..127; view: first node listed
  uint16_t index;        ///< SDO only (0 otherwise)
  uint8_t sub;           ///< SDO only
  uint16_t start;        ///< SDO: byte offset into the object (0 otherwise)
  uint16_t count;        ///< number of data; upload request: most bytes wanted (0: all that fit)
  uint32_t object_size;  ///< SDO download request, SDO responses: the whole object's size
  const uint8_t* data;   ///< `data_length` bytes: download / NMT / upload + view responses
  uint16_t data_length;
};

/// NMT command byte of a request's data (one byte; CiA 301 command specifiers).
inline uint8_t net_nmt_command(const NetMessage& m) {
  return m.data_length == 1u ? m.data[0] : 0u;
}

/// True when the PDU (FC first) is a 2Bh/0Dh request, whatever its body.
inline bool is_net_pdu(const uint8_t* pdu, uint16_t pdu_length) {
  return pdu_length >= 2u && pdu[0] == fc::kEncapsulatedInterface && pdu[1] == kMeiCanopenReference;
}

/// True when a 2Bh/0Dh request asks for the NMT service (protocol control
/// bits 6-7 = 1), whatever the rest: the one service of the function a
/// slave executes when it is broadcast (a write; SDO and the network view
/// return data, so a broadcast of them is ignored, as FC 17h's).
inline bool is_net_nmt_pdu(const uint8_t* pdu, uint16_t pdu_length) {
  return is_net_pdu(pdu, pdu_length) && pdu_length >= 3u && (pdu[2] >> net::kServiceShift) == 1u;
}

// ---- Slave side ---------------------------------------------------------

/// Parses a request PDU (FC first, `pdu_length` bytes) that is a 2Bh/0Dh
/// one (the slave hands the handler no other: its FC and MEI type are not
/// checked again). False: malformed,
/// answer exception 03 (wrong length for the service, reserved bits or bytes
/// not 0, a node id out of range, an NMT command CiA 301 does not define,
/// fields a service does not use not 0, a download part longer than its
/// object, a part before the last that is not a multiple of 7 bytes, an
/// upload window beyond 65535).
bool parse_net_request(const uint8_t* pdu, uint16_t pdu_length, NetMessage& out);

/// Writes the normal response `m` to `pdu` (at most `capacity` bytes) and
/// returns its length, 0 when it does not fit. `m.data` may point at the
/// place the data goes (pdu + net_data_offset()): then nothing is copied.
uint16_t build_net_response(uint8_t* pdu, uint16_t capacity, const NetMessage& m);
/// Where the data of a response of `service` starts in the PDU.
uint16_t net_response_data_offset(NetService service);
/// Turns the upload or network view request parsed from `pdu` into its
/// normal response in place and returns its length: the request's header
/// stays as it is (service, node id, index, subindex, starting address
/// echoed), with `more` and `count`, an upload's also the object `size`;
/// the `count` data bytes must already be at net_response_data_offset().
/// (A download's and an NMT response are the request as it stands:
/// net::kDownloadAnswerBytes, net::kNmtAnswerBytes.)
uint16_t answer_net_request(uint8_t* pdu, bool more, uint16_t count, uint32_t size);
/// Writes the exception response `code` (2 bytes).
uint16_t build_net_exception(uint8_t* pdu, Exception code);
/// Writes the exception-04 response carrying `abort_code` (7 bytes).
uint16_t build_net_abort(uint8_t* pdu, uint32_t abort_code);

// ---- Master side ---------------------------------------------------------

/// A complete request ADU (CRC included) to slave `address`, 0 when it does
/// not fit `capacity`. Fields are not checked (tests provoke exception 03).
uint16_t build_net_request(uint8_t* out, uint16_t capacity, uint8_t address, const NetMessage& m);
/// Convenience forms of build_net_request.
uint16_t build_net_upload(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t node_id, uint16_t index,
                          uint8_t sub, uint16_t start, uint16_t max_count);
/// One part of a download: `count` bytes at byte `start` of an object of
/// `object_size` bytes; `more` when further parts follow.
uint16_t build_net_download(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t node_id, uint16_t index,
                            uint8_t sub, uint32_t object_size, uint16_t start, const uint8_t* data,
                            uint16_t count, bool more);
uint16_t build_net_nmt(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t node_id, uint8_t command);
uint16_t build_net_view(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t first_node_id);

/// A decoded response: the normal one, an exception, or an SDO abort.
struct NetResponse {
  NetMessage message{};                    ///< valid with ParseStatus::kOk
  Exception exception = Exception::kNone;  ///< with ParseStatus::kException
  uint32_t abort_code = 0;                 ///< exception 04 with an SDO abort (0: a plain 04)
};

/// Checks `response` (ADU) as the answer to `request` (ADU built above): the
/// service, node id, index, subindex and starting address must be echoed.
ParseStatus parse_net_response(const uint8_t* request, uint16_t request_length, const uint8_t* response,
                               uint16_t response_length, NetResponse& out);

/// View entry `i` (< data_length / 4) of a network view response.
struct NetViewEntry {
  uint8_t node_id;
  uint8_t nmt_state;  ///< CiA 301 heartbeat state byte; net::kStateUnknown
  uint16_t age_ms;    ///< since its last heartbeat; net::kAgeSaturated: 65.535 s or more
};
NetViewEntry net_view_entry(const NetMessage& m, uint16_t i);
/// Writes one entry (for the slave side).
void put_net_view_entry(uint8_t* p, const NetViewEntry& e);

}  // namespace modbus
}  // namespace mb2co
