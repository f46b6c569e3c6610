// The master on its own SocketCAN interface: the poll() loop of bus_loop.h
// with the network of SDO clients (sdo_network.h) and NMT frames sent
// directly.
#pragma once
#include "bus_loop.h"
#include "transport.h"

namespace mb2co {
namespace master {

class CanTransport : public Transport {
 public:
  /// Opens o.iface (see BusLoop::open); with -v, tells how its frames move.
  Status open(const Options& o) override;

  std::unique_ptr<TransferNetwork> transfers(const Options& o) override;
  Status nmt(canopen::NmtCommand command, uint8_t node) override;
  BusLoop* bus() override { return &bus_; }

 private:
  BusLoop bus_;
};

}  // namespace master
}  // namespace mb2co
