#include "signal_pipe.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <QSocketNotifier>

namespace mb2co {
namespace pcapp {

int SignalPipe::fds_[2] = {-1, -1};

void SignalPipe::handler(int signal_number) {
  const int saved = errno;
  const unsigned char b = static_cast<unsigned char>(signal_number);
  const ssize_t n = ::write(fds_[1], &b, 1);  // non-blocking: a full pipe drops the duplicate
  (void)n;
  errno = saved;
}

SignalPipe::SignalPipe(std::initializer_list<int> numbers, QObject* parent) : QObject(parent) {
  if (fds_[0] >= 0 || ::pipe2(fds_, O_CLOEXEC | O_NONBLOCK) != 0) return;
  notifier_ = new QSocketNotifier(fds_[0], QSocketNotifier::Read, this);
  connect(notifier_, &QSocketNotifier::activated, this, &SignalPipe::drain);
  ok_ = true;
  for (int s : numbers) {
    struct sigaction sa = {};
    sa.sa_handler = &SignalPipe::handler;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    ok_ = ok_ && sigaction(s, &sa, nullptr) == 0;
  }
}

SignalPipe::~SignalPipe() {
  delete notifier_;
  for (int& fd : fds_) {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
}

void SignalPipe::drain() {
  unsigned char b = 0;
  while (::read(fds_[0], &b, 1) == 1) emit received(b);
}

}  // namespace pcapp
}  // namespace mb2co
