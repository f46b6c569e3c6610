// Runs tests/modbus/pty_slave as a child process and follows its stdout, so a
// test can wait for "ready <path>" and for counter changes (--events) instead
// of sleeping. Closing its stdin (stop(), the destructor) makes it exit.
// Built on the shared tests/support/line_child.h.
#pragma once
#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "line_child.h"

namespace mb2co {
namespace modbus {
namespace test {

class SlaveProcess {
 public:
  /// Starts `program` with `args`; false (and error()) when it cannot run or
  /// does not print its ready line within `timeout`.
  bool start(const std::string& program, const std::vector<std::string>& args,
             std::chrono::milliseconds timeout = std::chrono::seconds(10));
  /// Closes its stdin and reaps it; returns its exit status (-1: killed/never ran).
  int stop();

  const std::string& device() const { return device_; }
  const std::string& error() const { return error_; }

  /// Waits until a line (after the ready line) satisfies `match`; lines
  /// before it are consumed. False on timeout or end of output.
  bool wait_line(const std::function<bool(const std::string&)>& match, std::chrono::milliseconds timeout,
                 std::string* line = nullptr) {
    return child_.wait_line(match, timeout, line);
  }

 private:
  mb2co::test::LineChild child_;  ///< kills and reaps the slave if still running
  bool started_ = false;
  std::string device_;
  std::string error_;
};

}  // namespace test
}  // namespace modbus
}  // namespace mb2co
