// The sockets of `serve`: one listening socket, a client per connection,
// each with its Session (serve_session.h), all on the bus loop's poll()
// (a PollWatcher): no thread per client, nothing blocks. A client's socket
// is read only while its session takes more (so a client that floods or
// does not read its answers waits on its own socket, and no other does),
// and written as its answers come.
//
// A connection beyond --max-clients gets one line, `[0] ERROR:102 ...`,
// and is closed. A client silent for the idle timeout (no byte from it,
// no request of its pending, nothing left to send) is closed without a
// word. A client that shuts its sending side down still gets every answer
// due (then the connection closes); one that is gone (the peer closed both
// sides, or a send fails) has its pending requests cancelled: a running
// transfer aborted on the bus, its queued ones dropped.
#pragma once
#include <stdint.h>

#include <deque>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "bus_loop.h"
#include "serve_backend.h"
#include "serve_listen.h"
#include "serve_session.h"

namespace mb2co {
namespace master {

struct ServerLimits {
  size_t max_clients = 8;
  /// 0: no idle timeout. At most 2,000,000 (33 min): the loop's wrapping
  /// µs clock compares times less than 2^31 µs apart.
  uint32_t idle_ms = 0;
  SessionLimits session;
};

class ServeServer : public PollWatcher {
 public:
  /// `log`: connections coming and going, one line each. `describe`: the
  /// gateway's part of `info`.
  ServeServer(ServeBackend& backend, const ServerLimits& limits, std::ostream& log);
  ~ServeServer();
  ServeServer(const ServeServer&) = delete;
  ServeServer& operator=(const ServeServer&) = delete;

  /// Listens at `a` (serve_listen.h); where() then says where.
  Status listen(const ListenAddress& a);
  const std::string& where() const { return where_; }
  /// An event line for every client (Session::event); the last ones are
  /// kept for the `log` of clients that connect later.
  void event(const std::string& line);
  size_t clients() const { return clients_.size(); }

  void poll_fds(std::vector<pollfd>* fds) override;
  void on_poll(const pollfd* fds, size_t n, uint32_t now_us) override;
  void on_frame(const CanFrame&, uint32_t, const CanSink&) override {}
  /// Sends what the sessions got meanwhile; closes finished and idle clients.
  void process(uint32_t now_us, const CanSink& sink) override;
  void next_deadline(NextDeadline& d) const override;

 private:
  struct Client {
    int fd = -1;
    unsigned id = 0;
    std::unique_ptr<Session> session;
    uint32_t last_input_us = 0;
    bool input_ended = false;
    bool gone = false;  ///< to be closed (its session cancels what it asked)
    std::string why;    ///< why it is closed, for the log
  };
  void accept_clients(uint32_t now_us);
  void read_from(Client& c, uint32_t now_us);
  void write_to(Client& c);
  /// Closes the clients marked gone or finished.
  void sweep();
  std::string about() const;

  ServeBackend& backend_;
  ServerLimits limits_;
  std::ostream& log_;
  ListenAddress address_;
  int listen_fd_ = -1;
  std::string where_;
  std::vector<std::unique_ptr<Client>> clients_;
  std::deque<std::string> history_;  ///< the last session.log_lines events
  unsigned next_id_ = 1;
  std::vector<uint8_t> buffer_;  ///< one read's bytes
};

}  // namespace master
}  // namespace mb2co
