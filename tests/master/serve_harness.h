// What the tests of `mb2co-master serve` share: the server as a child
// (started, its listening line read) and a client that is not ours
// (tests/master/serve_client.py: Python's sockets, relaying lines as nc
// does), asked line by line. Waits poll for lines with deadlines that only
// bound a failure.
#pragma once
#include <chrono>
#include <string>
#include <vector>

#include "line_child.h"
#include "master_cli.h"

namespace mb2co {
namespace test {

/// `mb2co-master -i vcan0 ARGS... serve --listen LISTEN SERVE_ARGS...`.
class ServeProcess {
 public:
  /// Starts it and waits for "listening on ADDRESS"; false with the reason
  /// in error().
  bool start(const std::string& listen, const std::vector<std::string>& serve_args = {},
             const std::vector<std::string>& global_args = {"-t", "5000"});
  /// Where it listens, as it said (tcp: with the port the kernel chose).
  const std::string& where() const { return where_; }
  const std::string& error() const { return error_; }
  /// Waits for a line of its stdout containing `text` (events, connections).
  bool says(const std::string& text, std::string* line = nullptr);
  /// SIGTERM and its exit status.
  int stop();

  LineChild child;

 private:
  std::string where_;
  std::string error_;
};

/// serve_client.py connected to a server.
class ServeClient {
 public:
  /// Connects to `where` (unix:PATH or tcp:HOST:PORT); false when it cannot.
  bool open(const std::string& where);
  /// Sends `line` and returns the next line the server sends ("" on timeout).
  std::string ask(const std::string& line);
  /// Sends a directive or a line without waiting (see serve_client.py).
  bool send(const std::string& line) { return child.send_line(line); }
  /// The next line the server sent ("" on timeout, "eof" once it closed).
  std::string next();

  LineChild child;
};

/// RFC 4648 base64 decoding, written here from the RFC (independent of the
/// server's): the bytes of a `d`/`os` answer.
std::vector<uint8_t> base64_bytes(const std::string& text);

}  // namespace test
}  // namespace mb2co
