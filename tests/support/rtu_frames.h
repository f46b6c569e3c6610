// Raw Modbus/RTU frames for peer tests: what a master library offers no API
// for (FC 08, 2B/0E), deliberately broken frames (bad CRC, split by a gap),
// and reading a response straight from the serial file descriptor.
// The CRC here is the bitwise textbook algorithm, independent of
// shared/crc/crc16 (the code under test).
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <chrono>
#include <vector>

namespace mb2co {
namespace test {

using Bytes = std::vector<uint8_t>;

uint16_t crc16_bitwise(const uint8_t* data, size_t length);
/// `adu` (address + PDU) with its CRC appended, low byte first.
Bytes with_crc(Bytes adu);

/// Reads exactly `n` bytes from `fd` within `timeout`; false otherwise.
bool read_exact(int fd, uint8_t* out, size_t n, std::chrono::milliseconds timeout);
/// Reads one response ADU whose length follows from its header: exception,
/// FC 08 (echo of the request's `request_pdu_length` - 1 bytes), FC 2B/0E
/// (objects), FC 2B/0D (by service and number of data; its exception 04
/// with the abort code), FC 01-04 (byte count), FC 05 06 0F 10 (4 bytes). Returns it
/// without the CRC; empty on timeout or a wrong CRC.
Bytes read_response(int fd, size_t request_pdu_length, std::chrono::milliseconds timeout);
/// Discards and counts the bytes waiting on `fd` now (0: nothing was sent).
size_t drain(int fd);

}  // namespace test
}  // namespace mb2co
