// mb2co-master: a CANopen master on SocketCAN (seed 002's "Can
// Communicator" with network management), in the habits of can-utils and
// cocomm: one command per run, results on stdout, one-line errors on
// stderr, exit codes a script can use (exit_codes.h). With --via-modbus the
// SDO and NMT commands run through a gateway on a serial port instead.
#include <iostream>

#include "can_transport.h"
#include "cli_options.h"
#include "commands.h"
#include "exit_codes.h"
#include "gateway_transport.h"

using namespace mb2co::master;

int main(int argc, char** argv) {
  Options o;
  const mb2co::Status parsed = parse_options(argc, argv, &o);
  if (!parsed) {
    std::cerr << "mb2co-master: " << parsed.message() << "\n" << usage_text();
    return kExitUsage;
  }
  if (o.command == "help") {
    std::cout << usage_text();
    return kExitOk;
  }
  struct Command {
    const char* name;
    int (*run)(const Options&, Transport&, std::ostream&, std::ostream&);
  };
  static const Command kCommands[] = {{"scan", scan_command},         {"read", read_command},
                                      {"write", write_command},       {"upload", upload_command},
                                      {"download", download_command}, {"nmt", nmt_command},
                                      {"sync", sync_command},         {"watch", watch_command},
                                      {"dump", dump_command},         {"configure", configure_command}};
  const Command* command = nullptr;
  for (const Command& c : kCommands)
    if (o.command == c.name) command = &c;
  if (!command) {
    std::cerr << "mb2co-master: unknown command '" << o.command << "'\n" << usage_text();
    return kExitUsage;
  }
  const std::string refusal = via_modbus_refusal(o);
  if (!refusal.empty()) return fail(std::cerr, kExitUsage, refusal);
  if (!o.gateway_port.empty()) {
    static GatewayTransport gateway;
    const mb2co::Status opened = gateway.open(o);
    if (!opened) return fail(std::cerr, kExitBus, opened.message());
    return command->run(o, gateway, std::cout, std::cerr);
  }
  static CanTransport bus;
  const mb2co::Status opened = bus.open(o.iface.c_str());
  if (!opened) return fail(std::cerr, kExitBus, opened.message());
  return command->run(o, bus, std::cout, std::cerr);
}
