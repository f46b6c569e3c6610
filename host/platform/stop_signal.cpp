#include "platform/stop_signal.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

namespace mb2co {
namespace port {
namespace {
// Set by the handler, read by the loops.
volatile sig_atomic_t g_stop = 0;
// The pipe of stop_signal_fd(), {-1, -1} without one.
int g_pipe[2] = {-1, -1};
extern "C" void on_stop(int) {
  g_stop = 1;
  if (g_pipe[1] < 0) return;
  const int saved = errno;
  const char b = 1;
  const ssize_t n = write(g_pipe[1], &b, 1);  // non-blocking: a full pipe has woken the loop already
  (void)n;
  errno = saved;
}
}  // namespace

void catch_stop_signals() {
  struct sigaction sa = {};
  sa.sa_handler = on_stop;  // no SA_RESTART: poll() returns EINTR at once
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int stop_signal_fd() {
  if (g_pipe[0] < 0 && pipe2(g_pipe, O_CLOEXEC | O_NONBLOCK) != 0) return -1;
  catch_stop_signals();
  return g_pipe[0];
}

bool stop_requested() {
  return g_stop != 0;
}

void ignore_broken_pipes() {
  signal(SIGPIPE, SIG_IGN);
}

int poll_timeout_ms(const NextDeadline& d) {
  uint32_t at = 0;
  if (!d.result(&at)) return 100;
  const uint32_t wait_us = time_until(d.now_us(), at);
  return wait_us >= 100000u ? 100 : static_cast<int>((wait_us + 999u) / 1000u);
}

}  // namespace port
}  // namespace mb2co
