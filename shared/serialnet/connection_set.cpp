#include "serialnet/connection_set.h"

#include "platform/flash.h"

namespace mb2co {
namespace serialnet {
namespace {

// Seed 003 §3.2.4, first table: id bits, function-code bits, node-id bits,
// nodes per segment.
const ConnectionSet kSets[kConnectionSetCount] MB2CO_FLASH = {
    {11, 4, 7, 127},
    {8, 3, 5, 31},
    {7, 3, 4, 15},
    {6, 3, 3, 7},
};

// Seed 003 §3.2.4, second table: the 3-bit function codes. "Receive" and
// "transmit" are as seen by the node: its RPDO1 is what it consumes (200h+n),
// its receive SDO the request to it (600h+n).
const FunctionAssignment kFunctions[8] MB2CO_FLASH = {
    {0x000, 0x700},      // 0: NMT master message | heartbeat (NMT error control)
    {0x080, 0x080},      // 1: SYNC               | EMCY
    {0x100, 0x180},      // 2: TIME               | TPDO1
    {kReserved, 0x200},  // 3: reserved           | RPDO1
    {kReserved, 0x280},  // 4: reserved           | TPDO2
    {kReserved, 0x300},  // 5: reserved           | RPDO2
    {kReserved, 0x600},  // 6: reserved           | receive SDO
    {kReserved, 0x580},  // 7: reserved           | transmit SDO
};

const uint16_t kCanFunctionMask = 0x780;  // CiA 301: 4-bit function code
const uint16_t kCanNodeMask = 0x07F;

}  // namespace

ConnectionSet connection_set_at(uint8_t i) {
  return flash_read(&kSets[i < kConnectionSetCount ? i : 0]);
}

ConnectionSet connection_set(IdBits bits) {
  for (uint8_t i = 0; i < kConnectionSetCount; ++i) {
    const ConnectionSet s = connection_set_at(i);
    if (s.id_bits == static_cast<uint8_t>(bits)) return s;
  }
  return connection_set_at(0);
}

FunctionAssignment function_assignment(uint8_t code) {
  if (code >= 8) return FunctionAssignment{kReserved, kReserved};
  return flash_read(&kFunctions[code]);
}

MapResult can_to_serial(const ConnectionSet& set, uint16_t can_id, uint16_t* serial_id, uint8_t node_offset) {
  if (can_id > 0x7FFu) return MapResult::kIdOutOfRange;
  const uint16_t function = can_id & kCanFunctionMask;
  uint16_t node = can_id & kCanNodeMask;
  if (node != 0) {
    if (node <= node_offset) return MapResult::kNodeOutOfRange;
    node = static_cast<uint16_t>(node - node_offset);
  }
  if (set.id_bits == 11) {  // CAN's own set: the function code stays
    *serial_id = static_cast<uint16_t>(function | node);
    return MapResult::kOk;
  }
  for (uint8_t code = 0; code < 8; ++code) {
    const FunctionAssignment a = function_assignment(code);
    // SYNC (080h) and EMCY (080h+n) share a base: node 0 picks the former.
    const bool match = node == 0 ? a.can_id_node0 == can_id : a.can_base_node == function;
    if (!match) continue;
    if (node > set.max_nodes) return MapResult::kNodeOutOfRange;
    *serial_id = static_cast<uint16_t>((static_cast<uint16_t>(code) << set.node_bits) | node);
    return MapResult::kOk;
  }
  return MapResult::kNoFunctionCode;
}

MapResult serial_to_can(const ConnectionSet& set, uint16_t serial_id, uint16_t* can_id, uint8_t node_offset) {
  if (serial_id >> set.id_bits) return MapResult::kIdOutOfRange;
  const uint8_t node = node_id_of(set, serial_id);
  if (node != 0 && node + node_offset > kCanNodeMask) return MapResult::kNodeOutOfRange;
  const uint16_t can_node = node == 0 ? 0u : static_cast<uint16_t>(node + node_offset);
  if (set.id_bits == 11) {
    *can_id = static_cast<uint16_t>((serial_id & kCanFunctionMask) | can_node);
    return MapResult::kOk;
  }
  const FunctionAssignment a = function_assignment(function_code_of(set, serial_id));
  if (node == 0) {
    if (a.can_id_node0 == kReserved) return MapResult::kReservedCode;
    *can_id = a.can_id_node0;
  } else {
    *can_id = static_cast<uint16_t>(a.can_base_node + can_node);
  }
  return MapResult::kOk;
}

}  // namespace serialnet
}  // namespace mb2co
