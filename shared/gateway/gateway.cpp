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
      slave_(bank_, &identity_, ports.serial, 1, modbus::rtu_timing(ports.serial_baud))
#if MB2CO_GATEWAY_NET
      ,
      net_(node_, od_, slave_, ports.can, &values_.x2000_10_networkAccess)
#endif
{
#if MB2CO_GATEWAY_NET
  net_.attach();
#endif
  constexpr uint8_t kRanges = sizeof kNetworkServiceRanges / sizeof kNetworkServiceRanges[0];
  static_assert(kRanges <= kMaxServiceRanges, "the node has room for the network service's ranges");
  if (profile::kNetwork) node_.set_service_ranges(kNetworkServiceRanges, kRanges);
  node_.set_storage(ports.storage);
  node_.set_can_control(ports.can_control);
  node_.set_app_hook(&Gateway::app_write, this);
  node_.set_reset_callback(&Gateway::on_reset, this);
  node_.heartbeat_consumer().set_callback(&Gateway::on_heartbeat, this);
  node_.rpdos().set_callback(&Gateway::on_rpdo, this);
  line_.init(&od_, &values_);
}

void Gateway::start(uint32_t now_us, uint8_t default_node_id) {
  default_node_id_ = default_node_id;
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
  // Without saved parameters the id given at power-on stays in force.
  if (kind == kResetNode && !g.node_.params_loaded()) v.x2000_1_nodeId = g.default_node_id_;
  // Reset node with an id written and not saved, or the power-on reset that
  // loaded a saved id: 2000h/1 is this reset's id, and the node runs the
  // communication area's reset once more for it before its boot-up
  // (Node::reset); the rest is done then, once.
  g.node_.set_node_id_for_next_reset(v.x2000_1_nodeId);
  if (v.x2000_1_nodeId != g.node_.node_id()) return;
  // The one place the bit rate reaches the controller (platform/device_port.h): at
  // every reset, before the boot-up message leaves.
  const CanControl* can = g.node_.can_control();
  if (can != nullptr) {
    const CanControl control = flash_read(can);
    if (control.set_bitrate != nullptr) control.set_bitrate(g.node_.sink().ctx, v.x2000_2_bitrateKbit);
  }
  g.slave_.set_address(v.x2000_5_modbusAddress);
  g.line_.on_reset(g.node_.node_id());
  g.start_pending_ = v.x2000_8_selfStarting != 0;
}

void Gateway::on_heartbeat(void* ctx, uint8_t node_id, HbEvent event, uint8_t) {
  static_cast<Gateway*>(ctx)->line_.on_heartbeat(node_id, event);
}

void Gateway::on_rpdo(void* ctx, uint8_t n) {
  Gateway& g = *static_cast<Gateway*>(ctx);
  g.line_.on_rpdo(n, g.now_us_);
}

// Side effects only with `apply` (OdWriteHook): a refused Modbus request of
// several registers must not clear a latched stop or request a reset.
HookResult Gateway::app_write(void* ctx, uint8_t, uint16_t index, uint8_t sub, const uint8_t* data, uint16_t,
                              bool apply) {
  Gateway& g = *static_cast<Gateway*>(ctx);
  switch (index) {
    case 0x2000:
      if (sub == 2) {
        const uint16_t kbit = le16(data);
        if (kbit != 125 && kbit != 250 && kbit != 500 && kbit != 1000) return kAbortInvalidValue;
      }
      if (apply && sub == 1) g.node_.set_node_id_for_next_reset(data[0]);  // at reset communication
      return kSdoOk;
    case 0x2001:
      if (apply && data[0] != 0) g.node_.request_reset(data[0] == 1 ? kResetCommunication : kResetNode);
      return HookResult::handled();  // a request, not a setting: reads back 0
    case 0x2100:
      if (apply) g.line_.on_run_command(data[0]);
      return kSdoOk;
    default:
      // The Modbus maps are the register bank's: it decides what they may name.
      return OdRegisterBank::is_map_index(index) ? g.bank_.check_map_write(index, sub, data) : kSdoOk;
  }
}

uint8_t Gateway::process(uint32_t now_us, uint8_t raw_buttons) {
  now_us_ = now_us;
#if MB2CO_GATEWAY_NET
  net_.set_now(now_us);
#endif
  // 2003h for Modbus and SDO: the node counts at its resets (start(), an NMT
  // command, a pending reset), each followed by a pass that runs at once.
  values_.x2003_0_storageDamageCount = node_.storage_damage_count();
  slave_.process(now_us);
#if MB2CO_GATEWAY_NET
  net_.process(now_us);
#endif
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
#if MB2CO_GATEWAY_NET
  net_.next_deadline(d);
#endif
  return d.result(at_us);
}

}  // namespace gateway
}  // namespace mb2co
