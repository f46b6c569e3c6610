// SIGINT/SIGTERM end the programs on a serial segment cleanly (a pty's
// symlink is removed, --verbose counters printed): the handler only sets a
// flag; their poll() loops wake at least every 100 ms, and a signal
// interrupts poll() at once (EINTR). SIGPIPE is ignored (a closed pty peer).
#pragma once
#include "canopen/clock.h"

namespace mb2co {
namespace bridge {

/// Installs the handlers; call once at start.
void catch_stop_signals();
/// True once SIGINT or SIGTERM arrived.
bool stop_requested();
/// poll()'s timeout for deadline `d`: until it (rounded up to ms), at most 100 ms.
int poll_timeout_ms(const NextDeadline& d);

}  // namespace bridge
}  // namespace mb2co
