// SIGINT/SIGTERM as a flag: a signal only ends the current wait (poll()
// returns EINTR), the loop that waited reads stop_signalled() and ends
// cleanly (transfers aborted). Shared by the SocketCAN loop and the gateway
// link.
#pragma once

namespace mb2co {
namespace master {

/// Installs the handlers (no SA_RESTART, so a blocking poll() returns).
void catch_stop_signals();
/// A SIGINT or SIGTERM came since catch_stop_signals().
bool stop_signalled();

}  // namespace master
}  // namespace mb2co
