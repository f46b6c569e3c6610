#include "gateway/gateway.h"

namespace mb2co {
namespace gateway {

using namespace canopen;

Gateway::Gateway(const GatewayPorts& ports)
    : values_(),
      od_(od::GatewayDefinition, reinterpret_cast<uint8_t*>(&values_)),
      node_(od_, ports.can),
      bank_(od_),
      identity_(od_),
      slave_(bank_, &identity_, ports.serial, 1, modbus::rtu_timing(ports.serial_baud)),
      line_() {
  ports_storage_ = ports.storage;
  node_.set_storage(ports.storage);
  node_.set_app_hook(&Gateway::app_write, this);
  node_.set_reset_callback(&Gateway::on_reset, this);
  node_.heartbeat_consumer().set_callback(&Gateway::on_heartbeat, this);
  node_.rpdos().set_callback(&Gateway::on_rpdo, this);
  line_.init(&od_, &values_);
}

void Gateway::start(uint32_t now_us, uint8_t default_node_id) {
  default_node_id_ = default_node_id;
  now_us_ = now_us;
  // The node id is itself a saved parameter (2000h/1): read it before the
  // boot-up, so the node never announces itself under another id.
  uint8_t id = default_node_id;
  od_.restore_defaults(0x2000, 0x2000);
  if (ports_storage_ != nullptr && params_load(od_, *ports_storage_, 0x2000, 0x2000)) {
    id = values_.v_0x2000_1;
  }
  node_.start(id, now_us);
  slave_.begin(now_us);
}

void Gateway::on_reset(void* ctx, NmtReset kind) {
  Gateway& g = *static_cast<Gateway*>(ctx);
  od::GatewayValues& v = g.values_;
  // Without saved parameters the id given at power-on stays in force.
  if (kind == kResetNode && !g.node_.params_loaded()) v.v_0x2000_1 = g.default_node_id_;
  const uint8_t id = v.v_0x2000_1;
  if (id != g.node_.node_id()) {
    // 2000h/1 was changed since: reset once more with it, so that every
    // node-id-relative default follows.
    g.node_.set_node_id_for_next_reset(id);
    g.node_.request_reset(kResetCommunication);
  }
  g.bitrate_kbit_ = v.v_0x2000_2;
  g.slave_.set_address(v.v_0x2000_5);
  g.line_.on_reset(g.node_.node_id());
  g.start_pending_ = v.v_0x2000_8 != 0;
}

void Gateway::on_heartbeat(void* ctx, uint8_t node_id, HbEvent event, uint8_t) {
  static_cast<Gateway*>(ctx)->line_.on_heartbeat(node_id, event);
}

void Gateway::on_rpdo(void* ctx, uint8_t n) {
  Gateway& g = *static_cast<Gateway*>(ctx);
  g.line_.on_rpdo(n, g.now_us_);
}

uint32_t Gateway::app_write(void* ctx, uint8_t, uint16_t index, uint8_t sub, const uint8_t* data,
                            uint16_t) {
  Gateway& g = *static_cast<Gateway*>(ctx);
  switch (index) {
    case 0x2000:
      if (sub == 1) g.node_.set_node_id_for_next_reset(data[0]);  // at reset communication
      if (sub == 2) {
        const uint16_t kbit = le16(data);
        if (kbit != 125 && kbit != 250 && kbit != 500 && kbit != 1000) return kAbortInvalidValue;
      }
      return kSdoOk;
    case 0x2001:
      if (data[0] != 0) g.node_.request_reset(data[0] == 1 ? kResetCommunication : kResetNode);
      return kHookHandled;  // a request, not a setting: reads back 0
    case 0x2100:
      return g.line_.on_run_command(data[0]);
    case 0x2400:
    case 0x2401:
    case 0x2402:
    case 0x2403:
      return OdRegisterBank::check_map_write(g.od_, index, sub, data);
    default:
      return kSdoOk;
  }
}

uint8_t Gateway::process(uint32_t now_us, uint8_t raw_buttons) {
  now_us_ = now_us;
  slave_.process(now_us);
  const uint8_t leds =
      line_.process(now_us, raw_buttons, node_.nmt_state(), slave_.counters().server_messages);
  node_.process(now_us);
  if (start_pending_ && node_.nmt_state() == kNmtPreOperational) {
    start_pending_ = false;
    node_.local_nmt(kNmtStart, now_us);
  }
  return leds;
}

}  // namespace gateway
}  // namespace mb2co
