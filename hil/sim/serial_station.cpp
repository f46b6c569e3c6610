#include "sim/serial_station.h"

namespace mb2co {
namespace sim {

SerialStation::SerialStation(SerialBus& bus, int index, const serialnet::BusConfig& config, uint8_t node_id)
    : link(config, node_id, bus.port(index)), io(CanSink{&SerialStation::queue, this}), bus_(bus) {
  link.set_receiver(serialnet::CanReceiver{&SerialStation::receive, this});
  bus.attach(index, this);
}

void SerialStation::process(uint32_t now_us) {
  io.process(now_us);
  if (client_on) client.process(now_us, link.can_sink());
  link.process(now_us);
}

void SerialStation::next_deadline(NextDeadline& d) const {
  // Node::next_deadline is const in spirit; IoNode hands out its node non-const only.
  const_cast<SerialStation*>(this)->io.node().next_deadline(d);
  if (client_on) client.next_deadline(d);
  link.next_deadline(d);
}

void SerialStation::receive(void* ctx, const CanFrame& f, uint32_t now_us) {
  SerialStation& s = *static_cast<SerialStation*>(ctx);
  if (s.keep_received) s.received.emplace_back(now_us, f);
  s.io.receive(f, now_us);
  if (s.client_on) s.client.on_frame(f, now_us, s.link.can_sink());
}

bool SerialStation::queue(void* ctx, const CanFrame& f) {
  SerialStation& s = *static_cast<SerialStation*>(ctx);
  const bool queued = s.link.send(f);
  if (queued && s.on_queued) s.on_queued(f, s.bus_.now);
  return queued;
}

}  // namespace sim
}  // namespace mb2co
