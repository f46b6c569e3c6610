#include "remote_clock.h"

#include <cstdio>

#include "gateway/gateway_od.h"
#include "gateway/register_map.h"
#include "modbus_link.h"

namespace mb2co {
namespace pcapp {

namespace {

namespace e = gateway::od::GatewayEntry;

std::string hex_code(uint32_t code) {
  char b[16];
  std::snprintf(b, sizeof b, "%08Xh", static_cast<unsigned>(code));
  return b;
}

/// 06020000h: the object does not exist (CiA 301).
constexpr uint32_t kAbortNoObject = 0x06020000u;
/// 06090011h: the sub-index does not exist.
constexpr uint32_t kAbortNoSub = 0x06090011u;

}  // namespace

Status RemoteClock::probe(ModbusLink& link) {
  const uint16_t id_address = gateway::default_address(modbus::Table::kHoldingRegisters, e::x2000_1_nodeId);
  uint16_t id = 0;
  LinkResult r = link.holding_register(id_address, id);
  if (!r.ok()) return Status::failure("cannot read this station's node id (2000h/1): " + r.status.message());
  here_id_ = static_cast<uint8_t>(id);
  uint32_t watched = 0;
  uint32_t prev = 0;
  uint32_t abort = 0;
  r = link.upload(here_id_, 0x2130, 2, watched, abort);
  if (r.ok()) r = link.upload(here_id_, 0x2110, 4, prev, abort);
  if (!r.ok()) {
    return Status::failure("cannot read station " + std::to_string(here_id_) +
                           "'s neighbours by FC 2Bh/0Dh (2130h/2, 2110h/4): " + r.status.message());
  }
  remote_id_ = static_cast<uint8_t>(watched != 0 ? watched : prev);
  if (remote_id_ == 0) {
    return Status::failure("station " + std::to_string(here_id_) +
                           " is the first of its chain: no previous station whose button could be measured "
                           "(2110h/4 = 0, 2130h/2 = 0)");
  }
  Status s = clock_set(link, here_id_, set_here_us_);
  if (s) s = clock_set(link, remote_id_, set_remote_us_);
  return s;
}

Status RemoteClock::clock_set(ModbusLink& link, uint8_t node_id, uint32_t& set_us) {
  uint32_t abort = 0;
  const LinkResult r = link.upload(node_id, 0x2300, 4, set_us, abort);
  const std::string who = "station " + std::to_string(node_id);
  if (abort == kAbortNoObject || abort == kAbortNoSub)
    return Status::failure(who + " has no common clock (no 2300h/4: its image has no TIME)");
  if (!r.ok()) {
    return Status::failure(who + " unreachable: SDO upload of 2300h/4 by FC 2Bh/0Dh: " +
                           (abort != 0 ? "abort " + hex_code(abort) : r.status.message()));
  }
  if (set_us == 0) {
    return Status::failure(who +
                           "'s clock was never set by TIME (2300h/4 = 0): set 1012h's consumer bit "
                           "(80000100h) and run mb2co-master time --period MS");
  }
  return Status::ok();
}

Status RemoteClock::read_edge(ModbusLink& link, RemoteEdge& edge) {
  uint32_t abort = 0;
  const LinkResult r = link.upload(remote_id_, 0x2300, 1, edge.edge_us, abort);
  if (!r.ok()) {
    return Status::failure("station " + std::to_string(remote_id_) + " unreachable: SDO upload of 2300h/1: " +
                           (abort != 0 ? "abort " + hex_code(abort) : r.status.message()));
  }
  Status s = clock_set(link, remote_id_, edge.set_remote_us);
  if (s) s = clock_set(link, here_id_, edge.set_here_us);
  if (!s) return s;
  edge.prev_set_here_us = set_here_us_;
  edge.prev_set_remote_us = set_remote_us_;
  set_here_us_ = edge.set_here_us;
  set_remote_us_ = edge.set_remote_us;
  return s;
}

}  // namespace pcapp
}  // namespace mb2co
