// mb2co-node's set-up: what the node is wired to (its parameter file, the
// CAN trace, the pty or tty, SocketCAN), opened in the order in which a
// failure must leave nothing behind, and the gateway started on it with the
// command line's settings.
#pragma once
#include <string>

#include "canopen/param_storage.h"
#include "eeprom_file.h"
#include "gateway/gateway.h"
#include "host/can_log_file.h"
#include "host/status.h"
#include "node_options.h"
#include "platform/serial_port.h"
#include "platform/socketcan_port.h"
#include "traced_can.h"

namespace mb2co {
namespace node {

/// The node's ports and files. Not copyable (the trace and the storage
/// point into it).
struct NodeWiring {
  explicit NodeWiring(const NodeOptions& opt);
  NodeWiring(const NodeWiring&) = delete;
  NodeWiring& operator=(const NodeWiring&) = delete;

  /// A parameter file it could never save to is refused before anything is
  /// opened or created (no pty link, no CAN socket); so is a trace file it
  /// cannot create. Then the serial side, then the CAN interface. Fails
  /// with the line to print.
  Status open(const NodeOptions& opt);
  /// The ports the gateway core sends, stores and sets filters through.
  gateway::GatewayPorts gateway_ports(const NodeOptions& opt);
  /// What "ready" says of the serial side: the device, or --serial's "none".
  std::string serial_text(const NodeOptions& opt) const;

  EepromFile eeprom;
  canopen::ParamStorage storage;
  CanLogFile trace;
  port::SerialPort serial;
  const bool with_serial;  ///< false: Modbus/TCP only
  linux_port::SocketCanPort can;
  TracedCan traced_can;
  const bool with_can;
};

/// 1F50h/1: a large DOMAIN for segmented and block SDO transfers (program_data.h).
void serve_program_data(gateway::Gateway& gw);

/// Starts the gateway, warns of damaged saved parameters, and writes the
/// command line's bit rate, topology and station count as a technician
/// would over SDO (taking effect by a reset of communication). Fails with
/// the line to print when the dictionary refuses one.
Status start_gateway(gateway::Gateway& gw, const NodeOptions& opt);

}  // namespace node
}  // namespace mb2co
