#include "modbus_tcp_server.h"

#include <errno.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cstring>

namespace mb2co {
namespace node {

namespace {

// Connections waiting for accept() beyond the limit: they are taken (and
// the oldest unused one closed for them) pass by pass.
constexpr int kBacklog = 8;

uint64_t now_us() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

void set_option(int fd, int level, int name) {
  const int on = 1;
  setsockopt(fd, level, name, &on, sizeof on);  // a tuning: the server works without it
}

TcpAddress address_of(int fd) {
  sockaddr_storage ss{};
  socklen_t len = sizeof ss;
  TcpAddress a;
  if (getsockname(fd, reinterpret_cast<sockaddr*>(&ss), &len) != 0) return a;
  char host[NI_MAXHOST];
  char port[NI_MAXSERV];
  if (getnameinfo(reinterpret_cast<sockaddr*>(&ss), len, host, sizeof host, port, sizeof port,
                  NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
    a.host = host;
    a.port = static_cast<uint16_t>(std::strtoul(port, nullptr, 10));
  }
  return a;
}

}  // namespace

Status ModbusTcpServer::listen(const TcpAddress& where, size_t max_clients) {
  close();
  if (max_clients < 1 || max_clients > kMaxClients) return Status::failure("connection limit out of range");
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(where.port);
  const int rc = getaddrinfo(where.host.c_str(), port.c_str(), &hints, &found);
  if (rc != 0) return Status::failure("tcp " + where.text() + ": " + gai_strerror(rc));
  std::string why = "no address";
  for (addrinfo* a = found; a != nullptr && listen_fd_ < 0; a = a->ai_next) {
    const int fd = socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      why = std::strerror(errno);
      continue;
    }
    set_option(fd, SOL_SOCKET, SO_REUSEADDR);  // restart at once after a stop (guide §4.3.2)
    if (bind(fd, a->ai_addr, a->ai_addrlen) != 0 || ::listen(fd, kBacklog) != 0) {
      why = std::strerror(errno);
      ::close(fd);
      continue;
    }
    listen_fd_ = fd;
  }
  freeaddrinfo(found);
  if (listen_fd_ < 0) return Status::failure("tcp " + where.text() + ": " + why);
  max_clients_ = max_clients;
  bound_ = address_of(listen_fd_);
  return Status::ok();
}

size_t ModbusTcpServer::poll_fds(pollfd* fds) const {
  if (listen_fd_ < 0) return 0;
  fds[0] = pollfd{listen_fd_, POLLIN, 0};
  for (size_t i = 0; i < max_clients_; ++i) {
    const Connection& c = connections_[i];
    // Reading: the next bytes. Serving: only a hang-up (the client's
    // further requests wait in its socket). Sending: room for the rest.
    const short events = c.phase == Phase::kReading   ? POLLIN
                         : c.phase == Phase::kServing ? POLLRDHUP
                         : c.phase == Phase::kSending ? POLLOUT
                                                      : 0;
    fds[1 + i] = pollfd{c.phase == Phase::kFree ? -1 : c.fd, events, 0};
  }
  return 1 + max_clients_;
}

void ModbusTcpServer::handle(const pollfd* fds, size_t n) {
  if (listen_fd_ < 0 || n == 0) return;
  for (size_t i = 0; i + 1 < n && i < max_clients_; ++i) {
    Connection& c = connections_[i];
    if (c.broken) close_connection(c);  // a deferred answer that could not be sent
    const short got = fds[1 + i].revents;
    if (c.phase == Phase::kFree || fds[1 + i].fd != c.fd || got == 0) continue;
    if ((got & (POLLERR | POLLHUP | POLLNVAL)) != 0 ||
        (c.phase == Phase::kServing && (got & POLLRDHUP) != 0)) {
      close_connection(c);
    } else if (c.phase == Phase::kSending && (got & POLLOUT) != 0) {
      flush(c);
    } else if (c.phase == Phase::kReading && (got & POLLIN) != 0) {
      read_request(c);
    }
    if (c.broken) close_connection(c);
  }
  if ((fds[0].revents & POLLIN) != 0) accept_one();
}

void ModbusTcpServer::accept_one() {
  const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
  if (fd < 0) return;  // gone already, or out of descriptors: the next pass tries again
  // Answers leave at once (guide §4.3.2: no Nagle), a dead peer is noticed.
  set_option(fd, IPPROTO_TCP, TCP_NODELAY);
  set_option(fd, SOL_SOCKET, SO_KEEPALIVE);
  Connection* slot = nullptr;
  for (size_t i = 0; i < max_clients_ && slot == nullptr; ++i) {
    if (connections_[i].phase == Phase::kFree) slot = &connections_[i];
  }
  if (slot == nullptr) {
    slot = oldest_unused();
    if (slot == nullptr) {
      ++counters_.refused;
      ::close(fd);
      return;
    }
    ++counters_.evicted;
    close_connection(*slot);
  }
  ++counters_.accepted;
  slot->fd = fd;
  slot->phase = Phase::kReading;
  slot->rx.next();
  slot->channel = modbus::PduChannel{slot->rx.pdu(), &ModbusTcpServer::send_response, slot};
  slot->out_length = slot->out_sent = 0;
  slot->broken = false;
  slot->last_use_us = now_us();
  slot->server = this;
}

ModbusTcpServer::Connection* ModbusTcpServer::oldest_unused() {
  Connection* oldest = nullptr;
  for (size_t i = 0; i < max_clients_; ++i) {
    Connection& c = connections_[i];
    if (c.phase != Phase::kReading) continue;  // a request or an answer in hand
    if (oldest == nullptr || c.last_use_us < oldest->last_use_us) oldest = &c;
  }
  return oldest;
}

void ModbusTcpServer::read_request(Connection& c) {
  uint8_t bytes[modbus::kMaxMbapFrameBytes];
  for (;;) {
    const ssize_t got = ::read(c.fd, bytes, c.rx.wanted());
    if (got < 0 && (errno == EAGAIN || errno == EINTR)) return;  // the rest comes later
    if (got <= 0) {                                              // closed by the peer, or reset
      close_connection(c);
      return;
    }
    switch (c.rx.push(bytes, static_cast<uint16_t>(got))) {
      case modbus::MbapReceiver::Result::kNeedMore:
        continue;
      case modbus::MbapReceiver::Result::kBadLength:
        ++counters_.bad_length;
        close_connection(c);
        return;
      case modbus::MbapReceiver::Result::kForeign:
        ++counters_.foreign_frames;
        c.rx.next();
        return;  // one frame per pass: the next one in the next pass
      case modbus::MbapReceiver::Result::kRequest:
        ++counters_.requests;
        c.last_use_us = now_us();
        c.phase = Phase::kServing;
        // Answered from in here (send_response) or, deferred, from a later
        // Gateway::process(); until then the connection reads nothing.
        slave_.serve(c.channel, c.rx.pdu_length());
        return;
    }
  }
}

bool ModbusTcpServer::send_response(void* ctx, const uint8_t*, uint16_t length) {
  Connection& c = *static_cast<Connection*>(ctx);
  if (c.phase != Phase::kServing || c.broken) return false;
  c.out_length = c.rx.frame_response(length);  // the PDU was built at rx.pdu()
  c.out_sent = 0;
  c.phase = Phase::kSending;
  c.last_use_us = now_us();
  c.server->flush(c);
  return !c.broken;
}

void ModbusTcpServer::flush(Connection& c) {
  while (c.out_sent < c.out_length) {
    const ssize_t n = send(c.fd, c.rx.frame() + c.out_sent, c.out_length - c.out_sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN) return;  // POLLOUT brings the rest
    if (n <= 0) {
      c.broken = true;  // closed by the caller: the slave may be inside send_response
      return;
    }
    c.out_sent = static_cast<uint16_t>(c.out_sent + n);
  }
  c.phase = Phase::kReading;
  c.rx.next();
}

void ModbusTcpServer::close_connection(Connection& c) {
  if (c.phase == Phase::kFree) return;
  slave_.forget(c.channel);  // an answer deferred for it is dropped
  ::close(c.fd);
  c.fd = -1;
  c.phase = Phase::kFree;
  c.broken = false;
}

void ModbusTcpServer::close() {
  for (Connection& c : connections_) close_connection(c);
  if (listen_fd_ >= 0) ::close(listen_fd_);
  listen_fd_ = -1;
}

}  // namespace node
}  // namespace mb2co
