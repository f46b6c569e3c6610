// --via-modbus tcp:HOST:PORT: the gateway channel (gateway_link.h) over
// Modbus/TCP, to mb2co-node --tcp (docs/mb2co-node.md "Modbus/TCP").
// libmodbus's TCP backend opens the connection (modbus_new_tcp_pi: names
// and IPv6 too); the exchange is platform/mbap_client.h's (libmodbus 3.1
// cannot receive an FC 2Bh response): the codec's RTU ADU as an MBAP frame
// with our own transaction id, late answers skipped, the answer checked by
// the same codec as on the serial line.
#pragma once
#include <stdint.h>

#include <string>

#include "gateway_link.h"
#include "host/tcp_address.h"
#include "modbus/tcp_framer.h"

namespace mb2co {
namespace master {

class GatewayTcpLink : public GatewayChannel {
 public:
  GatewayTcpLink() = default;
  ~GatewayTcpLink() { close(); }
  GatewayTcpLink(const GatewayTcpLink&) = delete;
  GatewayTcpLink& operator=(const GatewayTcpLink&) = delete;

  /// Connects to `where`; requests carry unit id `unit` (0xFF: a server
  /// addressed by its IP address, the guide's value).
  Status open(const TcpAddress& where, uint8_t unit);
  void close();
  uint8_t unit() const { return unit_; }

  Exchange exchange(const uint8_t* request, uint16_t length, uint32_t timeout_ms,
                    modbus::NetResponse* out) override;
  std::string where() const override;

 private:
  modbus_t* ctx_ = nullptr;
  TcpAddress address_;
  uint8_t unit_ = modbus::kMbapUnitDirect;
  uint16_t transaction_ = 0;
  uint8_t adu_[modbus::kMaxAduBytes];
};

}  // namespace master
}  // namespace mb2co
