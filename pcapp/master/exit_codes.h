// mb2co-master's exit codes: what a script can tell apart without parsing
// the one-line error on stderr.
#pragma once

namespace mb2co {
namespace master {

enum ExitCode : int {
  kExitOk = 0,
  kExitRefused = 1,        ///< an SDO abort (its code is printed): the node's, or ours when the node
                           ///< broke the protocol or a bound (more bytes than it said or than we
                           ///< take, no progress in sequence); wrong identity
  kExitUsage = 2,          ///< bad command line or file (EDS/DCF/network file, value)
  kExitBus = 3,            ///< the CAN interface cannot be opened or refuses frames; --via-modbus: the
                           ///< port cannot be opened, the gateway does not answer or has no FC 2Bh/0Dh
  kExitNoAnswer = 4,       ///< a node did not answer in time (SDO timeout, node missing)
  kExitInterrupted = 130,  ///< SIGINT/SIGTERM ended a transfer (it was aborted on the bus)
};

}  // namespace master
}  // namespace mb2co
