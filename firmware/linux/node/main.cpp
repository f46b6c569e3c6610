// mb2co-node: the gateway firmware (the same shared/gateway code as on the
// Uno) on Linux: SocketCAN, a pty or tty for Modbus/RTU, buttons and LEDs on
// a line protocol over stdin/stdout. The set-up is node_setup.h's, the loop
// node_loop.h's; here the options and the exit status.
#include <errno.h>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>

#include "control_channel.h"
#include "gateway/gateway.h"
#include "modbus_tcp_server.h"
#include "node_loop.h"
#include "node_options.h"
#include "node_setup.h"
#include "platform/stop_signal.h"

namespace {

int fail(const std::string& what) {
  std::fprintf(stderr, "mb2co-node: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mb2co;
  const cli::Parsed parsed = cli::parse(node::program(), argc, argv);
  const int early = cli::finish_early(node::program(), parsed, std::cout, std::cerr);
  if (early >= 0) return early;
  node::NodeOptions opt;
  const Status applied = node::apply_options(parsed.args, &opt);
  if (!applied) {
    std::fprintf(stderr, "mb2co-node: %s\n", applied.message().c_str());
    return cli::kExitUsage;
  }

  // Signals from here on end the loop below, so that the pty link goes away.
  const int stop_fd = port::stop_signal_fd();
  if (stop_fd < 0) return fail(std::string("pipe: ") + std::strerror(errno));
  port::ignore_broken_pipes();

  node::NodeWiring wiring(opt);
  const Status opened = wiring.open(opt);
  if (!opened) return fail(opened.message());
  static gateway::Gateway gw(wiring.gateway_ports(opt));  // static like on the Uno (and large)
  node::ControlChannel control(gw);
  node::serve_program_data(gw);
  // Modbus/TCP in front of the same slave (modbus_tcp_server.h).
  node::ModbusTcpServer tcp(gw.modbus_slave());
  if (opt.tcp_given) {
    const Status listening = tcp.listen(opt.tcp, opt.tcp_clients);
    if (!listening) return fail(listening.message());
  }
  const Status started = node::start_gateway(gw, opt);
  if (!started) return fail(started.message());

  node::NodeLoop loop(opt, gw, control, tcp, wiring, stop_fd);
  const Status ran = loop.run();
  if (!ran) return fail(ran.message());
  const Status finished = loop.finish();
  if (!finished) return fail(finished.message());
  return 0;
}
