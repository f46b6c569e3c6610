// How mb2co-master reaches the CANopen network: its own SocketCAN
// interface (can_transport.h) or a Modbus/RTU gateway on a serial port that
// runs SDO and NMT on its CAN line for us (gateway_transport.h,
// --via-modbus). Commands that need raw CAN frames (watch, sync, block
// transfer, the heartbeat watchdog) get the SocketCAN loop from bus() and
// are refused up front through a gateway.
#pragma once
#include <stdint.h>

#include <memory>

#include "canopen/nmt_slave.h"
#include "cli_options.h"
#include "host/status.h"
#include "transfer_network.h"

namespace mb2co {
namespace master {

class BusLoop;

class Transport {
 public:
  virtual ~Transport() = default;
  /// Opens the CAN interface (-i) or the gateway's port (--via-modbus).
  /// Each command calls it once its operands are checked, so a usage error
  /// is exit 2 even where the interface is missing (3).
  virtual Status open(const Options& o) = 0;
  /// A fresh network of SDO transfers for one command, with the options'
  /// timeout and watchdog.
  virtual std::unique_ptr<TransferNetwork> transfers(const Options& o) = 0;
  /// Sends an NMT command to `node` (0: all). Fails with the reason the
  /// frame did not go out ("the CAN interface refused the frame: ...").
  virtual Status nmt(canopen::NmtCommand command, uint8_t node) = 0;
  /// The SocketCAN loop; null through a gateway.
  virtual BusLoop* bus() = 0;
};

}  // namespace master
}  // namespace mb2co
