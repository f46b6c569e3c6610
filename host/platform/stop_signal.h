// SIGINT/SIGTERM as a clean stop for every host program with a poll() loop
// (mb2co-master, mb2co-bridge, mb2co-serial-io-node, mb2co-serial-hub,
// mb2co-node, mb2co-uno): the handler only sets a flag (and wakes the
// stop_signal_fd() pipe when there is one); the loop that waited reads
// stop_requested() and ends cleanly (transfers aborted, a pty's symlink
// removed, counters printed). The handlers are installed without
// SA_RESTART, so a signal ends a blocking poll() at once (EINTR).
#pragma once
#include "canopen/clock.h"

namespace mb2co {
namespace port {

/// Installs the handlers; call once at start.
void catch_stop_signals();
/// As catch_stop_signals(), and returns a descriptor that becomes readable
/// when the signal comes, for a loop that polls other descriptors as well.
/// -1 when the pipe could not be made (errno says why). Call once.
int stop_signal_fd();
/// True once SIGINT or SIGTERM arrived after catch_stop_signals().
bool stop_requested();
/// Writes to a closed peer (a pty, a socket) fail with EPIPE instead of
/// ending the program.
void ignore_broken_pipes();
/// poll()'s timeout for deadline `d`: until it (rounded up to ms), at most
/// 100 ms, so a loop without a deadline still looks at stop_requested().
int poll_timeout_ms(const NextDeadline& d);

}  // namespace port
}  // namespace mb2co
