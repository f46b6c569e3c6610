// parse_response(): the master's checks of a response against its request.
#include <string.h>

#include "crc/crc16.h"
#include "modbus/master_codec.h"

namespace mb2co {
namespace modbus {
namespace {

// Normal response carrying `byte_count` data bytes after a byte-count field.
ParseStatus counted_data(const uint8_t* p, uint16_t pdu_length, uint16_t byte_count, Response& out) {
  if (byte_count > 0xFFu || p[1] != byte_count || pdu_length != 2u + byte_count) {
    return ParseStatus::kBadLength;
  }
  out.data = p + 2;
  out.data_length = byte_count;
  return ParseStatus::kOk;
}

ParseStatus diagnostics(const uint8_t* q, uint16_t request_pdu, const uint8_t* p, uint16_t pdu_length,
                        Response& out) {
  if (request_pdu < 3u) return ParseStatus::kBadRequest;
  if (pdu_length < 3u) return ParseStatus::kBadLength;
  if (p[1] != q[1] || p[2] != q[2]) return ParseStatus::kMismatch;
  out.data = p + 3;
  out.data_length = static_cast<uint16_t>(pdu_length - 3u);
  const uint16_t sub = get_be16(q + 1);
  if (sub == diag::kReturnQueryData) {  // the whole request comes back
    if (pdu_length != request_pdu) return ParseStatus::kBadLength;
    return memcmp(p, q, pdu_length) == 0 ? ParseStatus::kOk : ParseStatus::kMismatch;
  }
  if (pdu_length != 5u) return ParseStatus::kBadLength;
  const bool echoes =
      sub == diag::kRestartCommunications || sub == diag::kClearCounters || sub == diag::kClearOverrun;
  if (echoes && (request_pdu != 5u || memcmp(p + 3, q + 3, 2) != 0)) return ParseStatus::kMismatch;
  return ParseStatus::kOk;
}

ParseStatus device_id(const uint8_t* q, uint16_t request_pdu, const uint8_t* p, uint16_t pdu_length,
                      Response& out) {
  if (request_pdu != 4u) return ParseStatus::kBadRequest;
  if (pdu_length < 7u) return ParseStatus::kBadLength;
  if (p[1] != q[1] || p[2] != q[2]) return ParseStatus::kMismatch;
  out.conformity = p[3];
  out.more_follows = p[4];
  out.next_object = p[5];
  out.object_count = p[6];
  uint16_t pos = 7;
  for (uint8_t i = 0; i < out.object_count; ++i) {
    if (pos + 2u > pdu_length) return ParseStatus::kBadLength;
    pos = static_cast<uint16_t>(pos + 2u + p[pos + 1u]);
  }
  if (pos != pdu_length) return ParseStatus::kBadLength;
  out.data = p + 7;
  out.data_length = static_cast<uint16_t>(pdu_length - 7u);
  return ParseStatus::kOk;
}

}  // namespace

ParseStatus parse_response(const uint8_t* request, uint16_t request_length, const uint8_t* response,
                           uint16_t response_length, Response& out) {
  out = Response{};
  if (request_length < kMinAduBytes) return ParseStatus::kBadRequest;
  if (response_length < 5u) return ParseStatus::kTooShort;  // smallest: an exception
  if (!crc_ok(response, response_length)) return ParseStatus::kBadCrc;
  if (response[0] != request[0]) return ParseStatus::kWrongAddress;

  const uint8_t* q = request + 1;  // PDUs
  const uint8_t* p = response + 1;
  const uint16_t request_pdu = static_cast<uint16_t>(request_length - 1u - kCrcBytes);
  const uint16_t pdu_length = static_cast<uint16_t>(response_length - 1u - kCrcBytes);
  const uint8_t function = q[0];
  out.function = function;
  if (p[0] == (function | fc::kExceptionFlag)) {
    if (pdu_length != 2u) return ParseStatus::kBadLength;
    out.exception = static_cast<Exception>(p[1]);
    return ParseStatus::kException;
  }
  if (p[0] != function) return ParseStatus::kWrongFunction;

  switch (function) {
    case fc::kReadCoils:
    case fc::kReadDiscreteInputs:
      if (request_pdu != 5u) return ParseStatus::kBadRequest;
      return counted_data(p, pdu_length, packed_bit_bytes(get_be16(q + 3)), out);
    case fc::kReadHoldingRegisters:
    case fc::kReadInputRegisters:
    case fc::kReadWriteMultipleRegisters:  // read quantity at the same place
      if (request_pdu < 5u) return ParseStatus::kBadRequest;
      return counted_data(p, pdu_length, static_cast<uint16_t>(2u * get_be16(q + 3)), out);
    case fc::kWriteSingleCoil:
    case fc::kWriteSingleRegister:
    case fc::kWriteMultipleCoils:
    case fc::kWriteMultipleRegisters:
      // Single writes echo the request, multiple writes echo start and quantity.
      if (request_pdu < 5u) return ParseStatus::kBadRequest;
      if (pdu_length != 5u) return ParseStatus::kBadLength;
      return memcmp(p + 1, q + 1, 4) == 0 ? ParseStatus::kOk : ParseStatus::kMismatch;
    case fc::kDiagnostics:
      return diagnostics(q, request_pdu, p, pdu_length, out);
    case fc::kEncapsulatedInterface:
      return device_id(q, request_pdu, p, pdu_length, out);
    default:
      return ParseStatus::kBadRequest;
  }
}

bool device_id_object(const Response& response, uint8_t index, uint8_t& id, const uint8_t*& value,
                      uint8_t& length) {
  if (index >= response.object_count || response.data == nullptr) return false;
  uint16_t pos = 0;
  for (uint8_t i = 0; i < index; ++i) pos = static_cast<uint16_t>(pos + 2u + response.data[pos + 1u]);
  id = response.data[pos];
  length = response.data[pos + 1u];
  value = response.data + pos + 2u;
  return true;
}

}  // namespace modbus
}  // namespace mb2co
