// One client of `serve`: its byte stream in, CiA 309-3 answers out. Lines
// are parsed (ascii_request.h) and carried out through the backend as they
// come, several at once (a client may send before its last answer came:
// requests to different nodes run in parallel), and answered in the order
// they came (as CANopenNode, which takes one at a time, answers). No
// sockets, no clock: the server (serve_server.h) feeds bytes and sends what
// output() holds, so every answer can be tested without a bus.
//
// Bounded whatever the client does: a line longer than max_line is answered
// ERROR:600 and not kept (ascii_lines.h); beyond max_outstanding requests
// waiting for their answers, or max_output bytes of answers it did not read,
// the session takes no further line (wants_input() false: the server stops
// reading, so the client's socket fills and it waits).
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <deque>
#include <functional>
#include <string>

#include "ascii_lines.h"
#include "ascii_request.h"
#include "serve_backend.h"

namespace mb2co {
namespace master {

struct SessionLimits {
  uint16_t net = 1;                 ///< the net number this gateway answers to
  uint32_t sdo_timeout_ms = 1000;   ///< until `set sdo_timeout`
  size_t max_line = 256 * 1024;     ///< bytes of one request line (a 64 KiB value in hex fits)
  size_t max_value = 65536;         ///< bytes of a value written or read
  size_t max_outstanding = 64;      ///< requests waiting for their answers
  size_t max_output = 1024 * 1024;  ///< answers not yet sent before input pauses
  size_t log_lines = 256;           ///< events kept for `log`
};

class Session {
 public:
  /// `about`: the gateway's part of the `info` answer. Both outlive this.
  Session(ServeBackend& backend, const SessionLimits& limits, std::function<std::string()> about);
  /// Cancels what is still running for this client (ServeBackend::cancel).
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// Bytes from the client: complete lines are carried out (as far as the
  /// limits allow; the rest waits in the session).
  void receive(const uint8_t* data, size_t n);
  /// The client sent its last byte: an unfinished last line is answered
  /// ERROR:101 (ERROR:600 when too long), answers still due are sent.
  void end_of_input();
  /// A node state or EMCY line: kept for `log`, sent at once after `set events 1`.
  void event(const std::string& line);

  /// False while the session holds as many requests or answers as it may.
  bool wants_input() const;
  /// What to send.
  const std::string& output() const { return out_; }
  /// The first `n` bytes of output() went out: lines held back while the
  /// output was full are carried out now.
  void sent(size_t n);
  /// Input ended, every line answered: close once output() is sent.
  bool finished() const;
  /// Requests still waiting for their answers.
  size_t outstanding() const { return slots_.size(); }
  /// Events not sent because output() was full (never decrements).
  uint64_t events_dropped() const { return events_dropped_; }

 private:
  struct Slot {
    std::string text;  ///< the answer, once done
    bool done = false;
    bool has_ticket = false;
    ServeBackend::Ticket ticket = 0;
  };
  /// Carries out complete lines while the limits allow.
  void pump();
  void handle(const std::string& line);
  void handle_overlong(const std::string& prefix);
  /// Queues an answer known at once.
  void answer(std::string text);
  /// Moves the finished answers at the head to output().
  void flush();
  /// A read or write, answered into `slot` when the backend calls back.
  void start_sdo(const ascii::Request& r, Slot* slot);
  void start_nmt(const ascii::Request& r, Slot* slot);
  /// The backend answered `slot` (its text is set).
  void done(Slot* slot);
  std::string log_text();
  std::string info_text() const;

  ServeBackend& backend_;
  SessionLimits limits_;
  std::function<std::string()> about_;
  ascii::LineFramer framer_;
  std::deque<Slot> slots_;  ///< in request order; references stay valid (deque ends only)
  std::string out_;
  std::deque<std::string> log_;
  uint64_t log_dropped_ = 0;
  uint64_t events_dropped_ = 0;
  int16_t default_node_ = -1;
  uint32_t last_seq_ = 0;
  uint32_t sdo_timeout_ms_;
  bool sdo_block_ = false;
  bool events_ = false;
  bool ended_ = false;
};

}  // namespace master
}  // namespace mb2co
