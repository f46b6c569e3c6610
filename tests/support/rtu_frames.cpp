#include "rtu_frames.h"

#include <poll.h>
#include <unistd.h>

namespace mb2co {
namespace test {

uint16_t crc16_bitwise(const uint8_t* data, size_t length) {
  uint16_t crc = 0xFFFF;
  for (size_t i = 0; i < length; ++i) {
    crc ^= data[i];
    for (int b = 0; b < 8; ++b) {
      crc = (crc & 1) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001) : static_cast<uint16_t>(crc >> 1);
    }
  }
  return crc;
}

Bytes with_crc(Bytes adu) {
  const uint16_t crc = crc16_bitwise(adu.data(), adu.size());
  adu.push_back(static_cast<uint8_t>(crc));
  adu.push_back(static_cast<uint8_t>(crc >> 8));
  return adu;
}

bool read_exact(int fd, uint8_t* out, size_t n, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  size_t got = 0;
  while (got < n) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) return false;
    const ssize_t r = read(fd, out + got, n - got);
    if (r <= 0) return false;
    got += static_cast<size_t>(r);
  }
  return true;
}

Bytes read_response(int fd, size_t request_pdu_length, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  Bytes rsp;
  // Appends n bytes read within what is left of the timeout.
  auto take = [&](size_t n) {
    const size_t at = rsp.size();
    rsp.resize(at + n);
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    return read_exact(fd, rsp.data() + at, n, left);
  };
  if (!take(2)) return {};
  const uint8_t fc = rsp[1];
  bool ok = true;
  if (fc & 0x80) {
    ok = take(1);  // exception code
    // FC 2Bh/0Dh (requests of 12 bytes or more; 2Bh/0Eh's are 4): exception
    // 04 carries MEI 0Dh and the SDO abort code (docs/gateway-network.md).
    if (ok && fc == 0xAB && rsp[2] == 0x04 && request_pdu_length >= 12) ok = take(5);
  } else if (fc == 0x08) {
    ok = request_pdu_length >= 1 && take(request_pdu_length - 1);
  } else if (fc == 0x2B) {
    ok = take(1);  // MEI type
    if (ok && rsp[2] == 0x0D) {
      // Control .. number of data; then per service: upload size + data,
      // download size, NMT its command, view the entries.
      ok = take(10);
      const size_t count = ok ? static_cast<size_t>(rsp[11] << 8 | rsp[12]) : 0;
      const uint8_t service = ok ? static_cast<uint8_t>(rsp[3] & 0xE0) : 0;
      ok = ok && take(service == 0x00 ? 4 + count : service == 0x20 ? 4 : service == 0x60 ? 1 : count);
    } else {
      ok = ok && take(5);  // read code, conformity, more, next id, count
      for (uint8_t i = 0; ok && i < rsp[7]; ++i) ok = take(2) && take(rsp.back());
    }
  } else if ((fc >= 0x01 && fc <= 0x04) || fc == 0x17) {
    ok = take(1) && take(rsp[2]);  // byte count, data
  } else {
    ok = take(4);  // FC 05 06 0F 10: address and value/quantity
  }
  if (!ok || !take(2)) return {};
  const uint16_t crc = crc16_bitwise(rsp.data(), rsp.size() - 2);
  if (rsp[rsp.size() - 2] != static_cast<uint8_t>(crc) ||
      rsp[rsp.size() - 1] != static_cast<uint8_t>(crc >> 8)) {
    return {};
  }
  rsp.resize(rsp.size() - 2);
  return rsp;
}

size_t drain(int fd) {
  size_t total = 0;
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 0) <= 0) return total;
    uint8_t junk[512];
    const ssize_t n = read(fd, junk, sizeof junk);
    if (n <= 0) return total;
    total += static_cast<size_t>(n);
  }
}

}  // namespace test
}  // namespace mb2co
