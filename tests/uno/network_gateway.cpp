#include "network_gateway.h"

#include "uno_harness.h"

namespace mb2co {
namespace test {

std::unique_ptr<NodeProcess> start_network_gateway(const std::string& pty, std::chrono::milliseconds timeout,
                                                   std::string* error,
                                                   const std::vector<std::string>& extra) {
  std::unique_ptr<NodeProcess> gateway;
  bool started = false;
  if (network_gateway_is_uno()) {
    std::vector<std::string> argv{uno_program(), "--image", "network", "--can", "vcan0", "--pty", pty};
    argv.insert(argv.end(), extra.begin(), extra.end());
    gateway.reset(new UnoProcess);
    started = gateway->start_command(argv, timeout);
  } else {
    // Two stations: node 2, the remote mb2co-node, is its neighbour.
    std::vector<std::string> args{"--can", "vcan0", "--node-id", "1", "--stations", "2", "--pty", pty};
    args.insert(args.end(), extra.begin(), extra.end());
    gateway.reset(new NodeProcess);
    started = gateway->start(args, timeout);
  }
  if (started) return gateway;
  *error = std::string(network_gateway_name()) + ": " + gateway->error();
  return nullptr;
}

const char* network_gateway_name() {
  return network_gateway_is_uno() ? "mb2co-uno --image network" : "mb2co-node";
}

}  // namespace test
}  // namespace mb2co
