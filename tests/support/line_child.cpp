#include "line_child.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace mb2co {
namespace test {

namespace {

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

}  // namespace

bool LineChild::start(const std::vector<std::string>& argv) {
  if (pid_ > 0 || argv.empty()) {
    error_ = pid_ > 0 ? "already started" : "no program";
    return false;
  }
  ::signal(SIGPIPE, SIG_IGN);
  int in[2], out[2], err[2];
  if (pipe2(in, O_CLOEXEC) != 0 || pipe2(out, O_CLOEXEC) != 0 || pipe2(err, O_CLOEXEC) != 0) {
    error_ = std::string("pipe: ") + strerror(errno);
    return false;
  }
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t parent = getpid();
  pid_ = fork();
  if (pid_ == 0) {
    // Only async-signal-safe calls from here (the parent has threads).
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);  // the parent died already
    dup2(in[0], STDIN_FILENO);
    dup2(out[1], STDOUT_FILENO);
    dup2(err[1], STDERR_FILENO);
    execvp(args[0], args.data());
    static const char kMsg[] = "exec failed\n";
    const ssize_t n = write(STDERR_FILENO, kMsg, sizeof kMsg - 1);
    (void)n;
    _exit(127);
  }
  ::close(in[0]);
  ::close(out[1]);
  ::close(err[1]);
  stdin_fd_ = in[1];
  stdout_fd_ = out[0];
  stderr_fd_ = err[0];
  if (pid_ < 0) {
    error_ = std::string("fork: ") + strerror(errno);
    close_fd(stdin_fd_);
    close_fd(stdout_fd_);
    close_fd(stderr_fd_);
    return false;
  }
  thread_ = std::thread(&LineChild::reader, this);
  return true;
}

void LineChild::reader() {
  pollfd fds[2] = {{stdout_fd_, POLLIN, 0}, {stderr_fd_, POLLIN, 0}};
  while (fds[0].fd >= 0 || fds[1].fd >= 0) {
    if (poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      char buf[4096];
      const ssize_t n = read(fds[i].fd, buf, sizeof buf);
      if (n < 0 && errno == EINTR) continue;
      std::lock_guard<std::mutex> lock(mutex_);
      if (n <= 0) {
        fds[i].fd = -1;  // end of this stream
      } else if (i == 1) {
        stderr_.append(buf, static_cast<size_t>(n));
      } else {
        for (ssize_t k = 0; k < n; ++k) {
          if (buf[k] != '\n') {
            partial_ += buf[k];
            continue;
          }
          lines_.push_back(partial_);
          partial_.clear();
        }
      }
      changed_.notify_all();
    }
  }
  std::lock_guard<std::mutex> lock(mutex_);
  eof_ = true;
  changed_.notify_all();
}

bool LineChild::send_line(const std::string& line) {
  if (stdin_fd_ < 0) return false;
  const std::string data = line + "\n";
  size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = write(stdin_fd_, data.data() + done, data.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

void LineChild::close_stdin() {
  close_fd(stdin_fd_);
}

bool LineChild::signal(int sig) {
  return pid_ > 0 && status_ < 0 && kill(pid_, sig) == 0;
}

bool LineChild::wait_line(const std::function<bool(const std::string&)>& match,
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
    if (changed_.wait_until(lock, deadline) == std::cv_status::timeout && lines_.empty()) return false;
  }
}

bool LineChild::wait_prefix(const std::string& prefix, std::chrono::milliseconds timeout, std::string* line) {
  return wait_line([&](const std::string& l) { return l.compare(0, prefix.size(), prefix) == 0; }, timeout,
                   line);
}

int LineChild::wait_exit(std::chrono::milliseconds timeout) {
  if (pid_ <= 0) return status_;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!changed_.wait_for(lock, timeout, [this] { return eof_; })) return -1;
  }
  // Both outputs are closed: the child is exiting (or has exited).
  int ws = 0;
  while (waitpid(pid_, &ws, 0) < 0 && errno == EINTR) {
  }
  status_ = WIFEXITED(ws) ? WEXITSTATUS(ws) : WIFSIGNALED(ws) ? 128 + WTERMSIG(ws) : -1;
  pid_ = -1;
  stop();
  return status_;
}

std::string LineChild::stderr_text() {
  std::lock_guard<std::mutex> lock(mutex_);
  return stderr_;
}

void LineChild::stop() {
  close_fd(stdin_fd_);
  if (thread_.joinable()) thread_.join();
  close_fd(stdout_fd_);
  close_fd(stderr_fd_);
}

LineChild::~LineChild() {
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    int ws = 0;
    while (waitpid(pid_, &ws, 0) < 0 && errno == EINTR) {
    }
  }
  stop();
}

std::string field_of(const std::string& line, const std::string& name) {
  const std::string key = " " + name + "=";
  const size_t at = line.find(key);
  if (at == std::string::npos) return std::string();
  const size_t from = at + key.size();
  return line.substr(from, line.find(' ', from) - from);
}

}  // namespace test
}  // namespace mb2co
