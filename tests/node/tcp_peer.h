// A raw Modbus/TCP client for the mb2co-node tests: a blocking socket,
// frames written byte for byte as the Modbus Messaging on TCP/IP
// Implementation Guide lays them out, answers read with a deadline that
// only bounds a failure. Header-only; the tests check bytes themselves.
#pragma once
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace mb2co {
namespace test {

using TcpBytes = std::vector<uint8_t>;

/// An MBAP frame: transaction, protocol 0 (or `protocol`), length, unit, PDU.
inline TcpBytes mbap(uint16_t transaction, uint8_t unit, const TcpBytes& pdu, uint16_t protocol = 0) {
  const size_t length = pdu.size() + 1u;
  TcpBytes f = {static_cast<uint8_t>(transaction >> 8),
                static_cast<uint8_t>(transaction),
                static_cast<uint8_t>(protocol >> 8),
                static_cast<uint8_t>(protocol),
                static_cast<uint8_t>(length >> 8),
                static_cast<uint8_t>(length),
                unit};
  f.insert(f.end(), pdu.begin(), pdu.end());
  return f;
}

class TcpPeer {
 public:
  TcpPeer() = default;
  ~TcpPeer() { close(); }
  TcpPeer(const TcpPeer&) = delete;
  TcpPeer& operator=(const TcpPeer&) = delete;

  /// "HOST:PORT" as mb2co-node's ready line names it.
  bool connect(const std::string& address) {
    const size_t colon = address.rfind(':');
    if (colon == std::string::npos) return false;
    addrinfo hints{};
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (getaddrinfo(address.substr(0, colon).c_str(), address.substr(colon + 1).c_str(), &hints, &found) != 0)
      return false;
    fd_ = socket(found->ai_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const bool ok = fd_ >= 0 && ::connect(fd_, found->ai_addr, found->ai_addrlen) == 0;
    freeaddrinfo(found);
    const int on = 1;
    if (ok) setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
    return ok;
  }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  bool send(const TcpBytes& bytes) {
    return fd_ >= 0 &&
           ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
  }
  /// One whole frame by its length field; {} on timeout or a closed stream.
  TcpBytes frame(std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    return read_frame(fd_, timeout);
  }
  /// The same on any socket (libmodbus's: it cannot receive FC 2Bh).
  static TcpBytes read_frame(int fd, std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    TcpBytes f;
    if (!read_exactly(fd, 7, &f, timeout)) return {};
    const size_t length = static_cast<size_t>(f[4] << 8 | f[5]);
    if (length < 1 || !read_exactly(fd, length - 1u, &f, timeout)) return {};
    return f;
  }
  /// The answer's PDU to `pdu` sent as transaction `transaction`, unit
  /// `unit`, after checking that the header echoes both; {} otherwise.
  TcpBytes ask(uint16_t transaction, uint8_t unit, const TcpBytes& pdu) {
    if (!send(mbap(transaction, unit, pdu))) return {};
    const TcpBytes f = frame();
    if (f.size() < 8 || f[0] != (transaction >> 8) || f[1] != (transaction & 0xFF) || f[2] != 0 ||
        f[3] != 0 || f[6] != unit)
      return {};
    return TcpBytes(f.begin() + 7, f.end());
  }
  /// True when the server closed the connection within `timeout` (end of
  /// stream or reset; bytes before it are read and dropped).
  bool closed_by_server(std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
      pollfd p{fd_, POLLIN, 0};
      if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) return false;
      uint8_t junk[256];
      const ssize_t n = ::recv(fd_, junk, sizeof junk, 0);
      if (n <= 0) return true;
    }
  }
  /// True when nothing arrives within `quiet` (and the stream stays open).
  bool silent_for(std::chrono::milliseconds quiet) {
    pollfd p{fd_, POLLIN, 0};
    return poll(&p, 1, static_cast<int>(quiet.count())) == 0;
  }
  int fd() const { return fd_; }

 private:
  static bool read_exactly(int fd, size_t n, TcpBytes* out, std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (n > 0) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
      pollfd p{fd, POLLIN, 0};
      if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) return false;
      uint8_t buf[300];
      const ssize_t got = ::recv(fd, buf, n < sizeof buf ? n : sizeof buf, 0);
      if (got <= 0) return false;
      out->insert(out->end(), buf, buf + got);
      n -= static_cast<size_t>(got);
    }
    return true;
  }

  int fd_ = -1;
};

}  // namespace test
}  // namespace mb2co
