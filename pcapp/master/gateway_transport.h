// --via-modbus PORT[:SLAVE] | tcp:HOST:PORT: the master's SDO and NMT
// through an mb2co gateway on a serial port or on Modbus/TCP (FC 2Bh / MEI
// 0Dh), no CAN interface on this PC. The gateway runs each transfer with its own SDO client on its CAN
// line; what needs raw CAN frames (watch, sync, block transfer, the
// heartbeat watchdog) is refused before we get here (via_modbus_refusal).
#pragma once
#include "gateway_link.h"
#include "gateway_tcp_link.h"
#include "transport.h"

namespace mb2co {
namespace master {

/// How long the gateway may take for one request: its documented bound for
/// a remote SDO transfer of one frame's worth of data
/// (docs/gateway-network.md), plus the frames on the serial line.
uint32_t gateway_response_timeout_ms(const Options& o);

class GatewayTransport : public Transport {
 public:
  /// Opens o.gateway_port at o.baud and o.parity for o.gateway_slave, or
  /// connects to o.gateway_tcp (unit id o.gateway_slave).
  Status open(const Options& o) override;

  std::unique_ptr<TransferNetwork> transfers(const Options& o) override;
  Status nmt(canopen::NmtCommand command, uint8_t node) override;
  BusLoop* bus() override { return nullptr; }

 private:
  GatewayLink serial_;
  GatewayTcpLink tcp_;
  GatewayChannel* channel_ = &serial_;  ///< the one open()ed
  uint8_t slave_ = 1;                   ///< its Modbus address (TCP: unit id)
  uint32_t timeout_ms_ = 0;
};

}  // namespace master
}  // namespace mb2co
