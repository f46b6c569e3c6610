#include "serialnet/bridge.h"

#include "canopen/flash.h"

namespace mb2co {
namespace serialnet {
namespace {

const uint16_t kFunctionMask = 0x780;
const uint16_t kNodeMask = 0x07F;
const uint16_t kNmt = 0x000;
const uint16_t kSync = 0x080;

enum Direction : uint8_t { kToCan, kToSerial };

/// Seed 003 §3.2.8's lookup table: which CAN function (node id > 0) crosses
/// the bridge, and which way. Functions not listed do not cross.
struct Route {
  uint16_t can_base;
  Direction direction;
};
const Route kRoutes[] MB2CO_FLASH = {
    {0x080, kToCan},     // EMCY
    {0x180, kToCan},     // TPDO1
    {0x280, kToCan},     // TPDO2
    {0x580, kToCan},     // SDO response (server → client)
    {0x700, kToCan},     // boot-up, heartbeat
    {0x200, kToSerial},  // RPDO1
    {0x300, kToSerial},  // RPDO2
    {0x600, kToSerial},  // SDO request (client → server)
};
const uint8_t kRouteCount = sizeof(kRoutes) / sizeof(kRoutes[0]);

bool routed(uint16_t can_id, Direction direction) {
  const uint16_t function = can_id & kFunctionMask;
  for (uint8_t i = 0; i < kRouteCount; ++i) {
    const Route r = flash_read(&kRoutes[i]);
    if (r.can_base == function) return r.direction == direction;
  }
  return false;
}

}  // namespace

BridgeConfigError check_bridge_config(const BridgeConfig& config) {
  if (check_config(config.bus) != ConfigError::kOk) return BridgeConfigError::kBus;
  if (config.bus.access != Access::kPoller && config.bus.access != Access::kTokenStarter)
    return BridgeConfigError::kAccess;
  if (config.bridge_node < config.bus.first_node || config.bridge_node > config.bus.last_node)
    return BridgeConfigError::kBridgeNode;
  if (config.bus.last_node + config.node_offset > kNodeMask) return BridgeConfigError::kOffset;
  return BridgeConfigError::kOk;
}

bool serial_node_of(const BridgeConfig& config, uint16_t can_node, uint8_t* serial_node) {
  if (can_node <= config.node_offset) return false;
  const uint16_t n = static_cast<uint16_t>(can_node - config.node_offset);
  if (n < config.bus.first_node || n > config.bus.last_node || n == config.bridge_node) return false;
  *serial_node = static_cast<uint8_t>(n);
  return true;
}

bool bridges_clash(const BridgeConfig& a, const BridgeConfig& b) {
  uint8_t unused = 0;
  for (uint16_t n = a.bus.first_node; n <= a.bus.last_node; ++n) {
    if (n != a.bridge_node && serial_node_of(b, static_cast<uint16_t>(n + a.node_offset), &unused))
      return true;
  }
  return false;
}

bool FrameFifo::push(const CanFrame& f) {
  if (count_ == kCapacity) return false;
  frames_[(head_ + count_) % kCapacity] = f;
  ++count_;
  return true;
}

void FrameFifo::pop() {
  if (count_ == 0) return;
  head_ = static_cast<uint8_t>((head_ + 1u) % kCapacity);
  --count_;
}

Bridge::Bridge(const BridgeConfig& config, const modbus::ByteSink& line, const CanSink& can)
    : config_(config), can_(can), link_(config.bus, config.bridge_node, line) {
  link_.set_receiver(CanReceiver{&Bridge::receive, this});
}

void Bridge::receive(void* ctx, const CanFrame& f, uint32_t /*now_us*/) {
  static_cast<Bridge*>(ctx)->from_serial(f);
}

bool Bridge::extra_to_serial(uint16_t can_id) const {
  for (uint8_t i = 0; i < config_.extra_count; ++i) {
    if (config_.extra_to_serial[i] == can_id) return true;
  }
  return false;
}

bool Bridge::route_to_can(const CanFrame& in, CanFrame* out) {
  const uint16_t id = static_cast<uint16_t>(in.id);
  if (id == kSync) {  // a poll or a token pass: the segment's business
    bump(counters_.polls);
    return false;
  }
  uint8_t node = static_cast<uint8_t>(id & kNodeMask);
  if (node == 0 || node == config_.bridge_node || !routed(id, kToCan)) {
    bump(counters_.not_consumed);
    return false;
  }
  // The link hands us CAN ids of the segment's node ids: back to the serial
  // id, then to CAN with the offset (function code by the set's table).
  uint16_t serial_id = 0;
  uint16_t can_id = 0;
  if (can_to_serial(config_.bus.set, id, &serial_id) != MapResult::kOk ||
      serial_to_can(config_.bus.set, serial_id, &can_id, config_.node_offset) != MapResult::kOk) {
    bump(counters_.unmappable);
    return false;
  }
  *out = in;
  out->id = can_id;
  return true;
}

bool Bridge::route_to_serial(const CanFrame& in, CanFrame* out) {
  if (in.extended() || in.rtr()) {
    bump(counters_.unmappable);
    return false;
  }
  const uint16_t id = static_cast<uint16_t>(in.id);
  *out = in;
  if (id == kNmt) {
    // The target byte names a CAN node: ours get their serial id, 0 (all
    // nodes) stays; a command for a node elsewhere stays on CAN.
    uint8_t node = 0;
    if (in.dlc < 2) {
      bump(counters_.not_consumed);
      return false;
    }
    if (in.data[1] != 0) {
      if (!serial_node_of(config_, in.data[1], &node)) {
        bump(counters_.not_consumed);
        return false;
      }
      out->data[1] = node;
    }
    return true;
  }
  if (id == kSync) {
    bump(counters_.can_syncs);
    return false;
  }
  uint8_t node = 0;
  const bool to_our_node = serial_node_of(config_, id & kNodeMask, &node) && routed(id, kToSerial);
  if (!to_our_node && !extra_to_serial(id)) {
    bump(counters_.not_consumed);
    return false;
  }
  uint16_t serial_id = 0;
  uint16_t link_id = 0;
  if (can_to_serial(config_.bus.set, id, &serial_id, config_.node_offset) != MapResult::kOk ||
      serial_to_can(config_.bus.set, serial_id, &link_id) != MapResult::kOk) {
    bump(counters_.unmappable);
    return false;
  }
  out->id = link_id;
  return true;
}

void Bridge::from_serial(const CanFrame& f) {
  CanFrame out;
  if (!route_to_can(f, &out)) return;
  if (to_can_.empty() && can_.send(can_.ctx, out)) {
    bump(counters_.to_can);
    return;
  }
  if (!to_can_.push(out)) bump(counters_.overflow);
}

void Bridge::on_can(const CanFrame& f, uint32_t /*now_us*/) {
  CanFrame out;
  if (!route_to_serial(f, &out)) return;
  if (to_serial_.empty() && link_.send(out)) {
    bump(counters_.to_serial);
    return;
  }
  if (!to_serial_.push(out)) bump(counters_.overflow);
}

void Bridge::flush() {
  while (!to_serial_.empty() && link_.send(to_serial_.front())) {
    to_serial_.pop();
    bump(counters_.to_serial);
  }
  while (!to_can_.empty() && can_.send(can_.ctx, to_can_.front())) {
    to_can_.pop();
    bump(counters_.to_can);
  }
}

void Bridge::process(uint32_t now_us) {
  flush();
  link_.process(now_us);
  flush();  // the link's window may have made room
}

void Bridge::next_deadline(NextDeadline& d) const {
  link_.next_deadline(d);
  // A refusing CAN port gets a retry soon; the link's room comes with its
  // window, which its own deadline covers.
  const uint32_t kCanRetryUs = 1000;
  if (!to_can_.empty()) d.in(kCanRetryUs);
}

}  // namespace serialnet
}  // namespace mb2co
