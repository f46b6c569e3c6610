// The FC 2Bh/0Dh gateway the network tests drive, node 1 on vcan0 with its
// Modbus slave on a pty: mb2co-uno --image network when this build has
// mb2co-gateway-network.elf, else mb2co-node (the Linux build of the same
// gateway). tests/uno/CMakeLists.txt's MB2CO_NET_GATEWAY says which.
#pragma once
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "node_harness.h"

namespace mb2co {
namespace test {

/// Starts the gateway with its pty linked at `pty` and `extra` arguments
/// (mb2co-uno: --trace-can); nullptr with the reason in *error when it does
/// not get ready within `timeout`.
std::unique_ptr<NodeProcess> start_network_gateway(const std::string& pty, std::chrono::milliseconds timeout,
                                                   std::string* error,
                                                   const std::vector<std::string>& extra = {});
/// "mb2co-uno --image network" or "mb2co-node": what the tests ran against.
const char* network_gateway_name();

}  // namespace test
}  // namespace mb2co
