#include "stop_signal.h"

#include <signal.h>

namespace mb2co {
namespace master {

namespace {
// Set by the handler, read by the loops.
volatile sig_atomic_t g_signalled = 0;
extern "C" void on_signal(int) {
  g_signalled = 1;
}
}  // namespace

void catch_stop_signals() {
  struct sigaction sa = {};
  sa.sa_handler = on_signal;  // no SA_RESTART: poll() returns EINTR at once
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool stop_signalled() {
  return g_signalled != 0;
}

}  // namespace master
}  // namespace mb2co
