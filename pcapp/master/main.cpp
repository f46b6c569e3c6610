// mb2co-master: a CANopen master on SocketCAN (seed 002's "Can
// Communicator" with network management), in the habits of can-utils and
// cocomm: one command per run, results on stdout, one-line errors on
// stderr, exit codes a script can use (exit_codes.h). The command line is
// the shared convention (docs/cli.md, cli_options.h). With --via-modbus the
// SDO and NMT commands run through a gateway on a serial port instead.
#include <iostream>

#include "can_transport.h"
#include "cli_options.h"
#include "commands.h"
#include "exit_codes.h"
#include "gateway_transport.h"

using namespace mb2co;
using namespace mb2co::master;

int main(int argc, char** argv) {
  const cli::Parsed parsed = cli::parse(program(), argc, argv);
  const int early = cli::finish_early(program(), parsed, std::cout, std::cerr);
  if (early >= 0) return early;  // --help, --version, --list-options, usage error
  Options o;
  const Status applied = apply_options(parsed.args, &o);
  if (!applied) return fail(std::cerr, kExitUsage, applied.message());
  const CommandFunction run = command_function(o.command);
  if (run == nullptr) return fail(std::cerr, kExitUsage, "no function for the command " + o.command);
  // Opened by the command once its operands are checked (Transport::open).
  static GatewayTransport gateway;
  static CanTransport bus;
  Transport& transport = o.gateway_port.empty() ? static_cast<Transport&>(bus) : gateway;
  return run(o, transport, std::cout, std::cerr);
}
