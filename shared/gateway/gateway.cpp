#include "gateway/gateway.h"

namespace mb2co {
namespace gateway {

using namespace canopen;

constexpr uint16_t Gateway::kNetworkWidest;
constexpr uint16_t Gateway::kWidestRange;

Gateway::Gateway(const GatewayPorts& ports)
    : GatewayState(),
      od_(od::GatewayDefinition, reinterpret_cast<uint8_t*>(&values_)),
      node_(od_, ports.can),
      bank_(od_),
      identity_(od_),
      slave_(bank_, &identity_, ports.serial, 1, modbus::rtu_timing(ports.serial_baud)),
      net_(node_, od_, slave_, now_us_, values_.x2000_10_networkAccess) {
  net_.attach();
  constexpr uint8_t kRanges = sizeof kNetworkServiceRanges / sizeof kNetworkServiceRanges[0];
  static_assert(kRanges <= kMaxServiceRanges, "the node has room for the network service's ranges");
  if (profile::kNetwork) node_.set_service_ranges(kNetworkServiceRanges, kRanges);
  node_.set_storage(ports.storage);
  node_.set_can_control(ports.can_control);
  od_.set_owner(kOwnerGateway, this);
  node_.set_reset_callback(&Gateway::on_reset, this);
  node_.heartbeat_consumer().set_callback(&Gateway::on_heartbeat, this);
  node_.rpdos().set_callback(&Gateway::on_rpdo, this);
  line_.init(&od_, &values_);
}

void Gateway::start(uint32_t now_us, uint8_t default_node_id) {
  now_us_ = now_us;
  // The node id is itself a saved parameter (2000h/1): the reset node of the
  // start loads it and names it the reset's id (on_reset) before the
  // boot-up, so the node never announces itself under another id.
  node_.start(default_node_id, now_us);
  slave_.begin(now_us);
  line_.start(now_us);
}

void Gateway::on_reset(void* ctx, NmtReset kind) {
  Gateway& g = *static_cast<Gateway*>(ctx);
  od::GatewayValues& v = g.values_;
  // 2000h/1-2 as every device keeps its id and bit rate (Node::take_node_id_and_bitrate);
  // the rest once, in the reset that boots up with this id.
  if (!g.node_.take_node_id_and_bitrate(kind, &v.x2000_1_nodeId, v.x2000_2_bitrateKbit)) return;
  g.slave_.set_address(v.x2000_5_modbusAddress);
  g.line_.on_reset(g.node_.node_id());
  g.start_pending_ = v.x2000_8_selfStarting != 0;
}

void Gateway::on_heartbeat(void* ctx, uint8_t node_id, HbEvent event, uint8_t) {
  static_cast<Gateway*>(ctx)->line_.on_heartbeat(node_id, event);
}

void Gateway::on_rpdo(void* ctx, uint8_t n) {
  Gateway& g = *static_cast<Gateway*>(ctx);
  g.follow_common_clock();
  g.line_.on_rpdo(n, g.now_us_);
}

// The RUN command reaches the line application only with `apply`
// (OdWriteHandler): a refused Modbus request of several registers must not
// clear a latched stop.
HookResult GatewayHandlers::run_command(void* gateway, uint16_t, uint8_t, const uint8_t* data, bool apply) {
  if (apply) static_cast<Gateway*>(gateway)->line_.on_run_command(data[0]);
  return kSdoOk;
}

uint8_t Gateway::process(uint32_t now_us, uint8_t raw_buttons) {
  now_us_ = now_us;  // also the network service's: a request may run from the slave's process()
  // 2003h for Modbus and SDO: the node counts at its resets (start(), an NMT
  // command, a pending reset), each followed by a pass that runs at once.
  values_.x2003_0_storageDamageCount = node_.storage_damage_count();
  slave_.process(now_us);
  net_.process(now_us);
  follow_common_clock();
  const uint8_t leds =
      line_.process(now_us, raw_buttons, node_.nmt_state(), slave_.counters().server_messages);
  node_.process(now_us);
  if (start_pending_ && node_.nmt_state() == kNmtPreOperational) {
    start_pending_ = false;
    node_.local_nmt(kNmtStart, now_us);
  }
  return leds;
}

bool Gateway::next_deadline(uint32_t now_us, uint32_t* at_us) const {
  NextDeadline d(now_us);
  // A reset made the node pre-operational: process() starts it.
  if (start_pending_ && node_.nmt_state() == kNmtPreOperational) d.now();
  uint32_t frame_end_us = 0;
  if (slave_.next_deadline(now_us, &frame_end_us)) d.at(frame_end_us);
  line_.next_deadline(d, node_.nmt_state(), slave_.counters().server_messages);
  node_.next_deadline(d);
  net_.next_deadline(d);
  return d.result(at_us);
}

}  // namespace gateway
}  // namespace mb2co
