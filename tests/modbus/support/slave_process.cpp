#include "slave_process.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace mb2co {
namespace modbus {
namespace test {

bool SlaveProcess::start(const std::string& program, const std::vector<std::string>& args,
                         std::chrono::milliseconds timeout) {
  int in[2], out[2];
  if (pipe2(in, O_CLOEXEC) != 0 || pipe2(out, O_CLOEXEC) != 0) {
    error_ = std::string("pipe: ") + strerror(errno);
    return false;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(program.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const int rc = posix_spawn(&pid_, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(in[0]);
  close(out[1]);
  stdin_fd_ = in[1];
  stdout_fd_ = out[0];
  if (rc != 0) {
    pid_ = -1;
    error_ = "spawn " + program + ": " + strerror(rc);
    return false;
  }
  thread_ = std::thread(&SlaveProcess::reader, this);
  std::string line;
  if (!wait_line([](const std::string& l) { return l.rfind("ready ", 0) == 0; }, timeout, &line)) {
    error_ = program + " printed no ready line";
    return false;
  }
  device_ = line.substr(6);
  return true;
}

void SlaveProcess::reader() {
  std::string partial;
  char buf[256];
  for (;;) {
    const ssize_t n = read(stdout_fd_, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    std::lock_guard<std::mutex> lock(mutex_);
    for (ssize_t i = 0; i < n; ++i) {
      if (buf[i] == '\n') {
        lines_.push_back(partial);
        partial.clear();
      } else {
        partial += buf[i];
      }
    }
    changed_.notify_all();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  eof_ = true;
  changed_.notify_all();
}

bool SlaveProcess::wait_line(const std::function<bool(const std::string&)>& match,
                             std::chrono::milliseconds timeout, std::string* line) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    while (!lines_.empty()) {
      std::string l = std::move(lines_.front());
      lines_.pop_front();
      if (match(l)) {
        if (line != nullptr) *line = l;
        return true;
      }
    }
    if (eof_) return false;
    if (changed_.wait_until(lock, deadline) == std::cv_status::timeout && lines_.empty()) {
      return false;
    }
  }
}

int SlaveProcess::stop() {
  if (stdin_fd_ >= 0) {
    close(stdin_fd_);
    stdin_fd_ = -1;
  }
  int status = -1;
  if (pid_ > 0) {
    int ws = 0;
    if (waitpid(pid_, &ws, 0) == pid_ && WIFEXITED(ws)) status = WEXITSTATUS(ws);
    pid_ = -1;
  }
  if (thread_.joinable()) thread_.join();
  if (stdout_fd_ >= 0) {
    close(stdout_fd_);
    stdout_fd_ = -1;
  }
  return status;
}

SlaveProcess::~SlaveProcess() { stop(); }

}  // namespace test
}  // namespace modbus
}  // namespace mb2co
