// mb2co-node's Modbus/TCP server (docs/mb2co-node.md "Modbus/TCP"): a
// listening socket and up to max_clients connections, each with its own
// MBAP receiver (modbus/tcp_framer.h), all served by the gateway's one
// SlaveCore (SlaveCore::serve): the same register map and FC 2Bh/0Dh as the
// RTU line, beside it or instead of it.
//
// Rules (the Modbus Messaging on TCP/IP Implementation Guide V1.0b where it
// has one):
// - Any unit id is served and echoed, as libmodbus's TCP server does (a
//   server on TCP is addressed by its IP address, §4.4.1.2); unit id 0 is no
//   broadcast there and is answered too.
// - One request per connection at a time, one per connection and loop pass:
//   the next is read only when the answer has left, so a client that
//   pipelines waits in its own socket, never in our memory, and no client
//   starves another. An FC 2Bh/0Dh the gateway defers (a remote SDO
//   transfer) is answered when done while the other connections and the
//   line are served; another 2Bh/0Dh meanwhile gets exception 06 from the
//   service, as on the line (one transfer at a time, §4.4.2.2).
// - A length field outside 2..254 ends the connection (the stream can no
//   longer be cut into frames); a frame of another protocol id is skipped
//   (§4.4.2.2); neither disturbs another connection. A peer that closes or
//   half-closes is closed; an answer deferred for it is dropped.
// - At the connection limit a new connection takes the place of the one
//   unused longest (no request in hand, §4.2.1 "close the oldest unused
//   connection"); when every one is busy the new one is closed at once.
// Buffers: one MBAP frame (260 bytes) per connection, request and response
// in place; nothing grows. Not thread-safe: the node's loop only.
#pragma once
#include <poll.h>
#include <stddef.h>
#include <stdint.h>

#include "host/status.h"
#include "host/tcp_address.h"
#include "modbus/slave.h"
#include "modbus/tcp_framer.h"

namespace mb2co {
namespace node {

class ModbusTcpServer {
 public:
  static constexpr size_t kMaxClients = 32;
  /// Entries poll_fds() fills at most: the listener and every connection.
  static constexpr size_t kMaxPollFds = 1 + kMaxClients;

  /// What happened so far (only grows).
  struct Counters {
    uint64_t accepted;
    uint64_t requests;        ///< whole requests handed to the slave
    uint64_t foreign_frames;  ///< frames of another protocol id, skipped
    uint64_t bad_length;      ///< connections closed for a length outside 2..254
    uint64_t evicted;         ///< connections closed for a newer one at the limit
    uint64_t refused;         ///< new connections closed at once: every one busy
  };

  explicit ModbusTcpServer(modbus::SlaveCore& slave) : slave_(slave), counters_() {}
  ~ModbusTcpServer() { close(); }
  ModbusTcpServer(const ModbusTcpServer&) = delete;
  ModbusTcpServer& operator=(const ModbusTcpServer&) = delete;

  /// Binds `where` (port 0: a free one) and listens for up to
  /// `max_clients` (1..kMaxClients) connections at once.
  Status listen(const TcpAddress& where, size_t max_clients);
  /// The address bound (its real port); valid after listen().
  const TcpAddress& address() const { return bound_; }
  bool listening() const { return listen_fd_ >= 0; }

  /// Fills fds[0, n) for poll() (n = 1 + max_clients; unused slots have fd
  /// -1) and returns n; 0 when not listening.
  size_t poll_fds(pollfd* fds) const;
  /// After poll(): accepts, reads, serves, sends and closes, one request per
  /// connection at most. `fds` as poll_fds() filled them.
  void handle(const pollfd* fds, size_t n);
  /// Closes every connection (answers deferred for them are dropped) and
  /// the listener.
  void close();

  const Counters& counters() const { return counters_; }

 private:
  enum class Phase : uint8_t { kFree, kReading, kServing, kSending };
  struct Connection {
    int fd = -1;
    Phase phase = Phase::kFree;
    modbus::MbapReceiver rx;
    modbus::PduChannel channel{nullptr, nullptr, nullptr};
    uint16_t out_length = 0;  ///< response bytes at rx.frame()
    uint16_t out_sent = 0;
    bool broken = false;       ///< a send failed: close it
    uint64_t last_use_us = 0;  ///< last request or answer: eviction takes the oldest
    ModbusTcpServer* server = nullptr;
  };

  static bool send_response(void* ctx, const uint8_t* pdu, uint16_t length);
  void accept_one();
  void read_request(Connection& c);
  void flush(Connection& c);
  void close_connection(Connection& c);
  /// The connection unused longest, or null when every one is in use.
  Connection* oldest_unused();

  modbus::SlaveCore& slave_;
  int listen_fd_ = -1;
  size_t max_clients_ = 0;
  TcpAddress bound_;
  Connection connections_[kMaxClients];  ///< never moved: the slave holds channels
  Counters counters_;
};

}  // namespace node
}  // namespace mb2co
