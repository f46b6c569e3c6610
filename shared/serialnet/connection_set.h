// The pre-defined connection sets of CANopen on a general serial network
// (seed 003 §3.2.4): how many identifier bits the line carries, how they split
// into function code and node id, and the 3-bit function-code assignment, as
// constant data; plus the one mapping to and from the 11-bit CAN identifiers
// of CiA 301's default connection set, which the node core speaks.
//
// The 11-bit set is CAN's own (4-bit function code, 7-bit node id): every
// standard id maps onto itself. The 8/7/6-bit sets use the 3-bit function
// codes below; a CAN id they have no code for (TPDO3/4, RPDO3/4, node
// guarding's RTR, LSS, ...) or a node id beyond the set's range is refused
// with a MapResult that says why, and nothing is sent.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace serialnet {

/// Identifier width of a connection set, in bits (the table's first column).
enum class IdBits : uint8_t { k11 = 11, k8 = 8, k7 = 7, k6 = 6 };

/// One row of seed 003's table. Invariant: id_bits = function_bits +
/// node_bits; max_nodes = 2^node_bits - 1 (node id 0 addresses no node).
struct ConnectionSet {
  uint8_t id_bits;
  uint8_t function_bits;
  uint8_t node_bits;
  uint8_t max_nodes;  ///< nodes per segment: ids 1..max_nodes
};

/// The four sets in table order (11, 8, 7, 6 bits).
const uint8_t kConnectionSetCount = 4;
/// Row `i` (0..3) of the table; an out-of-range `i` gives the 11-bit set.
ConnectionSet connection_set_at(uint8_t i);
/// The set with `bits` identifier bits.
ConnectionSet connection_set(IdBits bits);

/// What the 3-bit function codes carry (seed 003's second table), named by
/// the CAN service they stand for.
struct FunctionAssignment {
  /// CAN id of the service when the node-id field is 0 (NMT 000h, SYNC 080h,
  /// TIME 100h), kReserved when the code is reserved with node id 0.
  uint16_t can_id_node0;
  /// CAN function base the node id is added to when the field is > 0
  /// (heartbeat 700h, EMCY 080h, TPDO1 180h, ...).
  uint16_t can_base_node;
};
const uint16_t kReserved = 0xFFFF;
/// Row `code` (0..7) of the 3-bit assignment; out of range: both kReserved.
FunctionAssignment function_assignment(uint8_t code);

/// Why an identifier did not map (kOk: it did).
enum class MapResult : uint8_t {
  kOk,
  kNoFunctionCode,  ///< the set has no code for this CAN function (e.g. TPDO3)
  kNodeOutOfRange,  ///< node id outside 1..max_nodes of the set (after the offset)
  kReservedCode,    ///< serial id with a reserved code (3..7 with node id 0)
  kIdOutOfRange,    ///< id wider than the set's bits (or than 11)
};

/// CAN id (standard, < 800h) → serial id of `set`. `node_offset` is a
/// bridge's (seed 003 §3.2.8): CAN node ids offset+1..offset+max_nodes are
/// the segment's nodes 1..max_nodes; node id 0 (NMT, SYNC, TIME) stays 0.
/// On a refusal *serial_id is left alone.
MapResult can_to_serial(const ConnectionSet& set, uint16_t can_id, uint16_t* serial_id,
                        uint8_t node_offset = 0);
/// Serial id of `set` → CAN id (the node id plus `node_offset`, at most 127).
MapResult serial_to_can(const ConnectionSet& set, uint16_t serial_id, uint16_t* can_id,
                        uint8_t node_offset = 0);

/// Function code and node id fields of a serial id (for bridges: seed 003
/// §3.2.8 translates the code by table and offsets the node id).
inline uint8_t function_code_of(const ConnectionSet& set, uint16_t serial_id) {
  return static_cast<uint8_t>(serial_id >> set.node_bits);
}
inline uint8_t node_id_of(const ConnectionSet& set, uint16_t serial_id) {
  return static_cast<uint8_t>(serial_id & ((1u << set.node_bits) - 1u));
}

/// True for the CAN ids of the default SDO channels (580h+n, 600h+n, n > 0):
/// their unused trailing bytes are left off on the line (seed 003 §3.2.2).
inline bool is_default_sdo(uint16_t can_id) {
  return (can_id >= 0x581u && can_id <= 0x5FFu) || (can_id >= 0x601u && can_id <= 0x67Fu);
}

/// True for the CAN ids of PDOs in the default connection set (TPDO1 180h
/// to RPDO4 57Fh): process data, where only the newest value matters.
inline bool is_pdo(uint16_t can_id) {
  return can_id >= 0x181u && can_id <= 0x57Fu;
}

}  // namespace serialnet
}  // namespace mb2co
