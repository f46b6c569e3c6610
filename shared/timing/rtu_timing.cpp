#include "timing/rtu_timing.h"

#include "modbus/rtu_timing.h"

namespace mb2co {
namespace timing {
namespace {

constexpr uint16_t kAddressFunctionCrcBytes = 4;  // address 1, function 1, CRC 2

uint64_t div_ceil(uint64_t a, uint64_t b) {
  return (a + b - 1u) / b;
}

uint16_t packed_bytes(uint16_t bit_count) {
  return static_cast<uint16_t>((bit_count + 7u) / 8u);
}

}  // namespace

bool serial_format_valid(const SerialFormat& f) {
  return f.baud > 0 && f.data_bits >= 5 && f.data_bits <= 8 && f.stop_bits >= 1 && f.stop_bits <= 2;
}

uint8_t char_bits(const SerialFormat& f) {
  return static_cast<uint8_t>(1u + f.data_bits + (f.parity == modbus::Parity::kNone ? 0u : 1u) + f.stop_bits);
}

uint64_t serial_frame_ns_floor(const SerialFormat& f, uint16_t bytes) {
  return uint64_t{bytes} * char_bits(f) * 1000000000u / f.baud;
}

uint64_t serial_frame_ns_ceil(const SerialFormat& f, uint16_t bytes) {
  return div_ceil(uint64_t{bytes} * char_bits(f) * 1000000000u, f.baud);
}

// The silences come from the framer the slave runs (modbus/rtu_timing.h),
// so the bound uses exactly the t3.5 the firmware waits.
uint64_t t35_ns(const SerialFormat& f) {
  return uint64_t{modbus::rtu_timing(f.baud, char_bits(f)).t35_us} * 1000u;
}

uint64_t t15_ns(const SerialFormat& f) {
  return uint64_t{modbus::rtu_timing(f.baud, char_bits(f)).t15_us} * 1000u;
}

RtuExchange read_bits_exchange(uint16_t count) {
  // request: start 2, quantity 2; response: byte count 1, packed bits
  return RtuExchange{kAddressFunctionCrcBytes + 4,
                     static_cast<uint16_t>(kAddressFunctionCrcBytes + 1 + packed_bytes(count))};
}

RtuExchange read_registers_exchange(uint16_t count) {
  return RtuExchange{kAddressFunctionCrcBytes + 4,
                     static_cast<uint16_t>(kAddressFunctionCrcBytes + 1 + 2u * count)};
}

RtuExchange write_single_exchange() {
  // address 2, value 2 both ways
  return RtuExchange{kAddressFunctionCrcBytes + 4, kAddressFunctionCrcBytes + 4};
}

RtuExchange write_bits_exchange(uint16_t count) {
  // request: start 2, quantity 2, byte count 1, packed bits; response: start, quantity
  return RtuExchange{static_cast<uint16_t>(kAddressFunctionCrcBytes + 5 + packed_bytes(count)),
                     kAddressFunctionCrcBytes + 4};
}

RtuExchange write_registers_exchange(uint16_t count) {
  return RtuExchange{static_cast<uint16_t>(kAddressFunctionCrcBytes + 5 + 2u * count),
                     kAddressFunctionCrcBytes + 4};
}

TransactionTiming transaction_timing(const SerialFormat& f, const RtuExchange& x, uint64_t slave_end_ns,
                                     uint64_t master_end_ns, uint64_t slave_turnaround_ns) {
  TransactionTiming t;
  t.request_ns = serial_frame_ns_ceil(f, x.request_bytes);
  t.response_ns = serial_frame_ns_ceil(f, x.response_bytes);
  t.best_ns = serial_frame_ns_floor(f, x.request_bytes) + slave_end_ns +
              serial_frame_ns_floor(f, x.response_bytes) + master_end_ns;
  t.worst_ns = t.request_ns + slave_end_ns + slave_turnaround_ns + t.response_ns + master_end_ns;
  return t;
}

}  // namespace timing
}  // namespace mb2co
