#include "platform/serial_port.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

namespace mb2co {
namespace port {
namespace {

// How long write() waits for room in a full kernel queue before it gives up
// (a pty whose reader went away would otherwise block the firmware forever).
constexpr int kWriteStallTimeoutMs = 200;

bool baud_constant(uint32_t baud, speed_t& out) {
  struct Rate {
    uint32_t baud;
    speed_t constant;
  };
  static const Rate kRates[] = {
      {1200, B1200},     {2400, B2400},     {4800, B4800},       {9600, B9600},     {19200, B19200},
      {38400, B38400},   {57600, B57600},   {115200, B115200},   {230400, B230400}, {460800, B460800},
      {500000, B500000}, {921600, B921600}, {1000000, B1000000},
  };
  for (const Rate& r : kRates) {
    if (r.baud == baud) {
      out = r.constant;
      return true;
    }
  }
  return false;
}

bool make_raw(int fd) {
  termios t;
  if (tcgetattr(fd, &t) != 0) return false;
  cfmakeraw(&t);
  t.c_cflag |= CLOCAL | CREAD;
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  return tcsetattr(fd, TCSANOW, &t) == 0;
}

}  // namespace

uint32_t monotonic_us() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  const uint64_t us = static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
  return static_cast<uint32_t>(us);
}

SerialPort::~SerialPort() {
  close();
}

Status SerialPort::fail(const std::string& what) {
  Status failed = Status::failure(what + ": " + strerror(errno));
  close();
  return failed;
}

Status SerialPort::create_pty(const std::string& link_path) {
  close();
  fd_ = posix_openpt(O_RDWR | O_NOCTTY);
  if (fd_ < 0) return fail("posix_openpt");
  char name[128];
  if (grantpt(fd_) != 0 || unlockpt(fd_) != 0 || ptsname_r(fd_, name, sizeof name) != 0) {
    return fail("pty setup");
  }
  path_ = name;
  pty_slave_fd_ = open(name, O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (pty_slave_fd_ < 0) return fail("open " + path_);
  if (!make_raw(pty_slave_fd_)) return fail("raw mode on " + path_);
  if (fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL) | O_NONBLOCK) != 0) return fail("O_NONBLOCK");
  if (!link_path.empty()) {
    struct stat st;
    if (lstat(link_path.c_str(), &st) == 0) {
      if (!S_ISLNK(st.st_mode)) {
        errno = EEXIST;
        return fail("refusing to replace " + link_path);
      }
      if (unlink(link_path.c_str()) != 0) return fail("unlink " + link_path);
    }
    if (symlink(name, link_path.c_str()) != 0) return fail("symlink " + link_path);
    link_ = link_path;
  }
  return Status::ok();
}

Status SerialPort::open_tty(const std::string& path, uint32_t baud, modbus::Parity parity,
                            unsigned stop_bits) {
  close();
  speed_t speed;
  if (!baud_constant(baud, speed)) {
    errno = EINVAL;
    return fail("unsupported baud rate " + std::to_string(baud));
  }
  if (stop_bits != 1 && stop_bits != 2) {
    errno = EINVAL;
    return fail("stop bits must be 1 or 2");
  }
  fd_ = open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd_ < 0) return fail("open " + path);
  path_ = path;
  termios t;
  if (tcgetattr(fd_, &t) != 0) return fail("tcgetattr " + path);
  cfmakeraw(&t);
  t.c_cflag &= ~static_cast<tcflag_t>(CSIZE | PARENB | PARODD | CSTOPB);
  t.c_cflag |= CS8 | CLOCAL | CREAD;
  if (parity != modbus::Parity::kNone) t.c_cflag |= PARENB;
  if (parity == modbus::Parity::kOdd) t.c_cflag |= PARODD;
  if (stop_bits == 2) t.c_cflag |= CSTOPB;
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (cfsetispeed(&t, speed) != 0 || cfsetospeed(&t, speed) != 0 || tcsetattr(fd_, TCSANOW, &t) != 0) {
    return fail("configure " + path);
  }
  tcflush(fd_, TCIOFLUSH);
  return Status::ok();
}

void SerialPort::close() {
  if (!link_.empty()) {
    // Remove the link only while it still points at our device.
    char target[256];
    const ssize_t n = readlink(link_.c_str(), target, sizeof target - 1);
    if (n > 0 && path_ == std::string(target, static_cast<size_t>(n))) unlink(link_.c_str());
    link_.clear();
  }
  if (pty_slave_fd_ >= 0) ::close(pty_slave_fd_);
  if (fd_ >= 0) ::close(fd_);
  pty_slave_fd_ = -1;
  fd_ = -1;
  path_.clear();
}

Status SerialPort::read(uint8_t* bytes, uint32_t* stamps_us, size_t capacity, size_t* count) {
  *count = 0;
  if (fd_ < 0) {
    errno = EBADF;
    return Status::failure("read: port not open");
  }
  const uint32_t stamp = monotonic_us();
  const ssize_t n = ::read(fd_, bytes, capacity);
  if (n < 0) {
    if (errno == EAGAIN || errno == EINTR) return Status::ok();
    return Status::failure(std::string("read: ") + strerror(errno));
  }
  for (ssize_t i = 0; i < n; ++i) stamps_us[i] = stamp;
  *count = static_cast<size_t>(n);
  return Status::ok();
}

Status SerialPort::write(const uint8_t* data, size_t length) {
  size_t done = 0;
  while (done < length) {
    const ssize_t n = ::write(fd_, data + done, length - done);
    if (n > 0) {
      done += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno != EAGAIN) return Status::failure(std::string("write: ") + strerror(errno));
    pollfd p{fd_, POLLOUT, 0};
    if (poll(&p, 1, kWriteStallTimeoutMs) <= 0) return Status::failure("write: output queue stalled");
  }
  return Status::ok();
}

}  // namespace port
}  // namespace mb2co
