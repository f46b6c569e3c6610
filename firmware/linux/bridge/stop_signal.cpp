#include "stop_signal.h"

#include <signal.h>

namespace mb2co {
namespace bridge {
namespace {
volatile sig_atomic_t g_stop = 0;
void on_stop(int) {
  g_stop = 1;
}
}  // namespace

void catch_stop_signals() {
  struct sigaction sa = {};
  sa.sa_handler = on_stop;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
}

bool stop_requested() {
  return g_stop != 0;
}

int poll_timeout_ms(const NextDeadline& d) {
  uint32_t at = 0;
  if (!d.result(&at)) return 100;
  const uint32_t wait_us = time_until(d.now_us(), at);
  return wait_us >= 100000u ? 100 : static_cast<int>((wait_us + 999u) / 1000u);
}

}  // namespace bridge
}  // namespace mb2co
