// Modbus RTU timing (Modbus over serial line V1.02 §2.5): character and
// frame times at a baud rate and character format, the t1.5/t3.5 silences,
// the sizes of the request/response pairs the gateway serves, and the PC's
// poll cycle. Times in ns; `_floor` for lower bounds, `_ceil` for upper
// bounds, so that a bound is never optimistic through rounding.
#pragma once
#include <stdint.h>

#include "modbus/parity.h"

namespace mb2co {
namespace timing {

/// A serial character format. The Modbus default is 8E1 (11 bits).
struct SerialFormat {
  uint32_t baud = 115200;  ///< bit/s, > 0
  uint8_t data_bits = 8;   ///< RTU uses 8
  modbus::Parity parity = modbus::Parity::kEven;
  uint8_t stop_bits = 1;  ///< 1 or 2
};

/// baud > 0, 5..8 data bits, 1 or 2 stop bits: required by every function below.
bool serial_format_valid(const SerialFormat& f);

/// Bits per character: start + data + parity + stop (8E1, 8N2: 11).
uint8_t char_bits(const SerialFormat& f);

/// Time to send `bytes` (≤ 65535) back to back, in ns.
uint64_t serial_frame_ns_floor(const SerialFormat& f, uint16_t bytes);
uint64_t serial_frame_ns_ceil(const SerialFormat& f, uint16_t bytes);

/// t3.5, the end-of-frame silence: 3.5 character times rounded up to whole
/// µs, fixed at 1,750 µs above 19,200 baud; the value the slave's framer
/// (modbus::rtu_timing) waits.
uint64_t t35_ns(const SerialFormat& f);
/// t1.5, the longest allowed gap inside a frame: 1.5 character times rounded
/// up to whole µs, 750 µs above 19,200 baud.
uint64_t t15_ns(const SerialFormat& f);

/// Bytes of one request and its normal response (address, function, fields,
/// CRC 2).
struct RtuExchange {
  uint16_t request_bytes;
  uint16_t response_bytes;
};

/// FC 01/02: read `count` coils/discrete inputs.
RtuExchange read_bits_exchange(uint16_t count);
/// FC 03/04: read `count` registers.
RtuExchange read_registers_exchange(uint16_t count);
/// FC 05/06: write a single coil/register (the response echoes the request).
RtuExchange write_single_exchange();
/// FC 0F: write `count` coils.
RtuExchange write_bits_exchange(uint16_t count);
/// FC 10: write `count` registers.
RtuExchange write_registers_exchange(uint16_t count);

/// One transaction on the wire: request, the slave's end-of-frame silence,
/// the slave's turnaround, the response, the master's end detection.
struct TransactionTiming {
  uint64_t request_ns;   ///< request frame
  uint64_t response_ns;  ///< response frame
  uint64_t best_ns;      ///< turnaround 0
  uint64_t worst_ns;     ///< turnaround = slave_turnaround_ns
};

/// `slave_end_ns`: how long the slave waits to see the request ended (t3.5
/// per spec); `master_end_ns`: the same for the master (0 when it predicts
/// the length, as libmodbus does); `slave_turnaround_ns`: the slave's worst
/// time to start answering (e.g. one firmware loop).
TransactionTiming transaction_timing(const SerialFormat& f, const RtuExchange& x, uint64_t slave_end_ns,
                                     uint64_t master_end_ns, uint64_t slave_turnaround_ns);

}  // namespace timing
}  // namespace mb2co
