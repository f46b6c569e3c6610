#include "gateway_transport.h"

#include "gateway_network.h"

namespace mb2co {
namespace master {

namespace {
/// The gateway's bound for one remote request (docs/gateway-network.md).
const uint32_t kGatewayBoundMs = 2000;
/// Two 256-byte frames at 9600 baud and the scheduling of a busy host.
const uint32_t kLineMarginMs = 1000;
}  // namespace

uint32_t gateway_response_timeout_ms(const Options& o) {
  // -t is the SDO timeout of a node's answer; the gateway applies its own,
  // so the longer of the two bounds what we wait for.
  const uint32_t bound = o.timeout_ms > kGatewayBoundMs ? o.timeout_ms : kGatewayBoundMs;
  return bound + kLineMarginMs;
}

Status GatewayTransport::open(const Options& o) {
  timeout_ms_ = gateway_response_timeout_ms(o);
  slave_ = o.gateway_slave;
  if (o.gateway_on_tcp) {
    channel_ = &tcp_;
    return tcp_.open(o.gateway_tcp, o.gateway_slave);
  }
  channel_ = &serial_;
  return serial_.open(o.gateway_port, o.baud, o.gateway_slave, o.parity);
}

std::unique_ptr<TransferNetwork> GatewayTransport::transfers(const Options&) {
  return std::unique_ptr<TransferNetwork>(new GatewayNetwork(*channel_, slave_, timeout_ms_));
}

Status GatewayTransport::nmt(canopen::NmtCommand command, uint8_t node) {
  return gateway_nmt(*channel_, slave_, timeout_ms_, static_cast<uint8_t>(command), node);
}

}  // namespace master
}  // namespace mb2co
