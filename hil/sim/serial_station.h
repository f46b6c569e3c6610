// A real I/O node (shared/ionode: the unchanged node core) on the simulated
// serial line through a SerialLink, optionally with an SDO client sharing
// its link (a master). Frames the node core queues for the line pass through
// the station, which notes when (for latency measurements) and hands them on.
#pragma once
#include <stdint.h>

#include <functional>
#include <utility>
#include <vector>

#include "canopen/sdo_client.h"
#include "ionode/io_node.h"
#include "serialnet/serial_link.h"
#include "sim/serial_bus.h"

namespace mb2co {
namespace sim {

class SerialStation : public BusDevice {
 public:
  /// Joins `bus` as talker `index` (the bus must outlive the station).
  SerialStation(SerialBus& bus, int index, const serialnet::BusConfig& config, uint8_t node_id);

  serialnet::SerialLink link;
  ionode::IoNode io;
  canopen::SdoClient client{};
  bool client_on = false;
  /// Every frame handed to the node, when `keep_received` (long runs turn it off).
  std::vector<std::pair<uint32_t, CanFrame>> received;
  bool keep_received = true;
  /// Called with every frame the node core queues for the line, at bus time.
  std::function<void(const CanFrame& f, uint32_t now_us)> on_queued;

  canopen::Node& node() { return io.node(); }

  void on_byte(uint8_t byte, uint32_t byte_us) override { link.on_byte(byte, byte_us); }
  void process(uint32_t now_us) override;
  void next_deadline(NextDeadline& d) const override;

 private:
  static void receive(void* ctx, const CanFrame& f, uint32_t now_us);
  static bool queue(void* ctx, const CanFrame& f);

  SerialBus& bus_;
};

}  // namespace sim
}  // namespace mb2co
