// Master (client) side of Modbus/RTU without I/O: builds request ADUs for the
// function codes the slave serves and checks a received response against the
// request it answers. Used by the line simulator (virtual time) and tests.
#pragma once
#include <stdint.h>

#include "modbus/protocol.h"

namespace mb2co {
namespace modbus {

// ---- Requests. Each writes a complete ADU (CRC included) to out[0, capacity)
// and returns its length, 0 when it would not fit. Quantities are not checked
// against the spec limits, so that tests can provoke exception 03.

/// FC 01 02 03 04; returns 0 for another function code.
uint16_t build_read_request(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t function,
                            uint16_t start, uint16_t quantity);
uint16_t build_write_single_coil(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t coil, bool on);
uint16_t build_write_single_register(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t reg,
                                     uint16_t value);
/// FC 0F; `packed` holds packed_bit_bytes(quantity) bytes, LSB first.
uint16_t build_write_coils(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t start,
                           uint16_t quantity, const uint8_t* packed);
/// FC 10; `values` holds `quantity` registers.
uint16_t build_write_registers(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t start,
                               uint16_t quantity, const uint16_t* values);
/// FC 17; `values` holds `write_quantity` registers.
uint16_t build_read_write_registers(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t read_start,
                                    uint16_t read_quantity, uint16_t write_start, uint16_t write_quantity,
                                    const uint16_t* values);
/// FC 08 with an arbitrary data field (sub 00 echoes any data).
uint16_t build_diagnostics(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t sub,
                           const uint8_t* data, uint16_t data_length);
/// FC 08 with the usual 2-byte data field (0000 for the counters).
uint16_t build_diagnostics(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t sub, uint16_t data);
/// FC 2B / MEI 0E; code 1..3 stream access, 4 individual.
uint16_t build_read_device_id(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t code,
                              uint8_t object_id);

// ---- Responses.

enum class ParseStatus : uint8_t {
  kOk,
  kException,  ///< a well-formed exception response: see Response::exception
  kTooShort,   ///< fewer bytes than the smallest response
  kBadCrc,
  kWrongAddress,   ///< from another slave (or the request was a broadcast)
  kWrongFunction,  ///< neither the request's function code nor its exception form
  kBadLength,      ///< length or byte count inconsistent with the request
  kMismatch,       ///< an echoed field differs from the request
  kBadRequest,     ///< the request itself is not one the builders make
};

/// Points into the response buffer: valid while that buffer is.
struct Response {
  uint8_t function = 0;
  Exception exception = Exception::kNone;
  /// FC 01-04, 17: the data bytes after the byte count. FC 08: the data field
  /// after the sub-function. FC 2B: the object list. Others: empty.
  const uint8_t* data = nullptr;
  uint16_t data_length = 0;
  /// FC 2B only.
  uint8_t conformity = 0;
  uint8_t more_follows = 0;
  uint8_t next_object = 0;
  uint8_t object_count = 0;

  uint16_t reg(uint16_t i) const { return get_be16(data + 2u * i); }
  bool bit(uint16_t i) const { return packed_bit(data, i); }
  /// FC 08: the 2-byte data field (a counter value).
  uint16_t diag_value() const { return data_length >= 2u ? get_be16(data) : 0u; }
};

/// Checks `response` as the answer to `request` (both complete ADUs).
ParseStatus parse_response(const uint8_t* request, uint16_t request_length, const uint8_t* response,
                           uint16_t response_length, Response& out);

/// FC 2B: object number `index` (0-based, < object_count) of a parsed response.
bool device_id_object(const Response& response, uint8_t index, uint8_t& id, const uint8_t*& value,
                      uint8_t& length);

}  // namespace modbus
}  // namespace mb2co
