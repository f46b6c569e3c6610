// A program under test as a child process, talked to line by line: lines go
// to its stdin, its stdout and stderr are collected by a reader thread, so a
// test waits for what the program says (a deadline bounds only a failure)
// instead of sleeping.
//
// The child gets SIGKILL when the thread that started it ends (prctl
// PR_SET_PDEATHSIG), so a crashed test leaves nothing running: start it from
// the test's main thread. The destructor kills and reaps it if still running.
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
namespace test {

class LineChild {
 public:
  LineChild() = default;
  ~LineChild();
  LineChild(const LineChild&) = delete;
  LineChild& operator=(const LineChild&) = delete;

  /// Starts argv[0] (a path, or a name searched in PATH). False (and error())
  /// when it cannot be started.
  bool start(const std::vector<std::string>& argv);

  /// Writes `line` plus '\n' to its stdin (SIGPIPE is ignored in this
  /// process from the first start() on: a dead child gives false).
  bool send_line(const std::string& line);
  /// End of input for the child.
  void close_stdin();
  /// Sends a signal (false when it is not running).
  bool signal(int sig);

  /// Waits until a stdout line satisfies `match`; earlier lines are consumed.
  /// False on timeout or end of output.
  bool wait_line(const std::function<bool(const std::string&)>& match, std::chrono::milliseconds timeout,
                 std::string* line = nullptr);
  /// Waits for a line starting with `prefix`.
  bool wait_prefix(const std::string& prefix, std::chrono::milliseconds timeout, std::string* line = nullptr);

  /// Waits until the child has closed its output and exited: its exit code,
  /// 128 + N when killed by signal N, -1 on timeout (it is still running).
  int wait_exit(std::chrono::milliseconds timeout);

  /// Everything it wrote to stderr so far (complete once wait_exit returned).
  std::string stderr_text();
  pid_t pid() const { return pid_; }
  const std::string& error() const { return error_; }

 private:
  void reader();
  void stop();

  pid_t pid_ = -1;
  int status_ = -1;  ///< exit status once reaped
  int stdin_fd_ = -1;
  int stdout_fd_ = -1;
  int stderr_fd_ = -1;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::string> lines_;
  std::string partial_;
  std::string stderr_;
  bool eof_ = false;
  std::string error_;
};

/// Field `name=value` of a space-separated line ("state node=1 run=0 ..."):
/// the value, or "" when absent.
std::string field_of(const std::string& line, const std::string& name);

}  // namespace test
}  // namespace mb2co
