// Runs tests/modbus/pty_slave as a child process and follows its stdout, so a
// test can wait for "ready <path>" and for counter changes (--events) instead
// of sleeping. Closing its stdin (the destructor) makes it exit.
#pragma once
#include <sys/types.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

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
  ~SlaveProcess();

  const std::string& device() const { return device_; }
  const std::string& error() const { return error_; }

  /// Waits until a line (after the ready line) satisfies `match`; lines
  /// before it are consumed. False on timeout or end of output.
  bool wait_line(const std::function<bool(const std::string&)>& match,
                 std::chrono::milliseconds timeout, std::string* line = nullptr);

 private:
  void reader();

  pid_t pid_ = -1;
  int stdin_fd_ = -1;
  int stdout_fd_ = -1;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::string> lines_;
  bool eof_ = false;
  std::string device_;
  std::string error_;
};

}  // namespace test
}  // namespace modbus
}  // namespace mb2co
