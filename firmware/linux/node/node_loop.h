// mb2co-node's loop: one thread, one poll() loop that plays the Arduino's
// loop(), but sleeps until the next deadline of the gateway
// (Gateway::next_deadline) or an input instead of spinning: under a bus
// flood the CPU goes to frames, not to idle passes.
#pragma once
#include <poll.h>
#include <stdint.h>

#include <string>

#include "control_channel.h"
#include "gateway/gateway.h"
#include "host/status.h"
#include "modbus_tcp_server.h"
#include "node_options.h"
#include "node_setup.h"

namespace mb2co {
namespace node {

class NodeLoop {
 public:
  /// After start_gateway(): the "ready" line names the node id in force.
  NodeLoop(const NodeOptions& opt, gateway::Gateway& gw, ControlChannel& control, ModbusTcpServer& tcp,
           NodeWiring& wiring, int stop_fd);
  NodeLoop(const NodeLoop&) = delete;
  NodeLoop& operator=(const NodeLoop&) = delete;

  /// Runs until "quit" or SIGINT/SIGTERM; fails, with the line to print,
  /// when a port does.
  Status run();
  /// A clean exit keeps an answered save: its remaining passes first; then
  /// the ports and the trace close. Fails when the trace is incomplete.
  Status finish();

 private:
  static constexpr size_t kFds = 4 + ModbusTcpServer::kMaxPollFds;

  /// One pass at `now`: the serial bytes and commands that came, the
  /// timers, Modbus/TCP, then some CAN frames; true when it took frames.
  Status pass(pollfd* fds, size_t tcp_fds, uint32_t now, bool* frames_taken);
  void take_commands(uint32_t now);
  bool take_frames(const pollfd* fds);
  void say_ready();
  /// How long the next poll may sleep: until the earliest deadline.
  uint32_t sleep_us(uint32_t now) const;

  const NodeOptions& opt_;
  gateway::Gateway& gw_;
  ControlChannel& control_;
  ModbusTcpServer& tcp_;
  NodeWiring& wiring_;
  const int stop_fd_;
  /// Said once the Modbus slave accepts frames; "" after.
  std::string ready_;
  std::string input_;  ///< stdin not yet taken as whole lines
  bool stdin_open_ = true;
};

}  // namespace node
}  // namespace mb2co
