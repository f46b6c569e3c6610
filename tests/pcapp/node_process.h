// mb2co-node as a child process for link tests: started on a pty link in a
// fresh directory, ready once it printed its "ready" line.
#pragma once
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

namespace mb2co {
namespace pcapp {

class NodeProcess {
 public:
  /// Starts `MB2CO_NODE_BIN --can none --pty <dir>/tty`; ready() tells
  /// whether its "ready" line came within `timeout_ms`.
  explicit NodeProcess(int timeout_ms = 10000) {
    char dir[] = "/tmp/mb2co-pcapp-node-XXXXXX";
    if (mkdtemp(dir) == nullptr) return;
    dir_ = dir;
    tty_ = dir_ + "/tty";
    int out[2];
    int in[2];
    if (pipe(out) != 0 || pipe(in) != 0) return;
    pid_ = fork();
    if (pid_ == 0) {
      dup2(in[0], 0);
      dup2(out[1], 1);
      close(in[1]);
      close(out[0]);
      execl(MB2CO_NODE_BIN, MB2CO_NODE_BIN, "--can", "none", "--pty", tty_.c_str(),
            static_cast<char*>(nullptr));
      _exit(127);
    }
    close(in[0]);
    close(out[1]);
    stdin_ = in[1];
    stdout_ = out[0];
    std::string line;
    while (read_line(line, timeout_ms)) {
      if (line.rfind("ready ", 0) == 0) {
        ready_ = true;
        break;
      }
    }
  }
  ~NodeProcess() {
    kill(SIGTERM);
    if (stdin_ >= 0) close(stdin_);
    if (stdout_ >= 0) close(stdout_);
    if (!tty_.empty()) unlink(tty_.c_str());
    if (!dir_.empty()) rmdir(dir_.c_str());
  }
  bool ready() const { return ready_; }
  const std::string& tty() const { return tty_; }
  void kill(int sig) {
    if (pid_ <= 0) return;
    ::kill(pid_, sig);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  bool read_line(std::string& line, int timeout_ms) {
    line.clear();
    for (char c;;) {
      pollfd p{stdout_, POLLIN, 0};
      if (poll(&p, 1, timeout_ms) <= 0 || ::read(stdout_, &c, 1) != 1) return false;
      if (c == '\n') return true;
      line += c;
    }
  }

  pid_t pid_ = -1;
  int stdin_ = -1;
  int stdout_ = -1;
  std::string dir_;
  std::string tty_;
  bool ready_ = false;
};

}  // namespace pcapp
}  // namespace mb2co
