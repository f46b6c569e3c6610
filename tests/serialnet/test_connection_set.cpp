// The connection sets of seed 003 §3.2.4 as data, and the mapping between
// serial identifiers and 11-bit CAN identifiers: both ways, and refusals.
#include <gtest/gtest.h>

#include "serialnet/connection_set.h"

namespace mb2co {
namespace serialnet {
namespace {

TEST(ConnectionSet, TableIsSeed003) {
  struct Row {
    IdBits bits;
    uint8_t fc, node, max;
  };
  const Row rows[] = {
      {IdBits::k11, 4, 7, 127}, {IdBits::k8, 3, 5, 31}, {IdBits::k7, 3, 4, 15}, {IdBits::k6, 3, 3, 7}};
  for (uint8_t i = 0; i < kConnectionSetCount; ++i) {
    const ConnectionSet s = connection_set_at(i);
    EXPECT_EQ(s.id_bits, static_cast<uint8_t>(rows[i].bits));
    EXPECT_EQ(s.function_bits, rows[i].fc);
    EXPECT_EQ(s.node_bits, rows[i].node);
    EXPECT_EQ(s.max_nodes, rows[i].max);
    EXPECT_EQ(s.function_bits + s.node_bits, s.id_bits);
    EXPECT_EQ(s.max_nodes, (1u << s.node_bits) - 1u);
    EXPECT_EQ(connection_set(rows[i].bits).id_bits, s.id_bits);
  }
}

TEST(ConnectionSet, ThreeBitFunctionCodesAreSeed003) {
  // {code, CAN id with node 0 (or reserved), CAN base with node > 0}
  const uint16_t expected[8][2] = {{0x000, 0x700},     {0x080, 0x080},     {0x100, 0x180},
                                   {kReserved, 0x200}, {kReserved, 0x280}, {kReserved, 0x300},
                                   {kReserved, 0x600}, {kReserved, 0x580}};
  for (uint8_t code = 0; code < 8; ++code) {
    const FunctionAssignment a = function_assignment(code);
    EXPECT_EQ(a.can_id_node0, expected[code][0]) << int(code);
    EXPECT_EQ(a.can_base_node, expected[code][1]) << int(code);
  }
  EXPECT_EQ(function_assignment(8).can_base_node, kReserved);
}

// The services of the default connection set every short set carries, for
// node n (0: the broadcast ones).
struct Service {
  uint16_t can_base;
  uint8_t code;
  bool node0;
};
const Service kServices[] = {
    {0x000, 0, true},  {0x080, 1, true},  {0x100, 2, true},                      // NMT, SYNC, TIME
    {0x700, 0, false}, {0x080, 1, false}, {0x180, 2, false}, {0x200, 3, false},  // HB, EMCY, TPDO1, RPDO1
    {0x280, 4, false}, {0x300, 5, false}, {0x600, 6, false}, {0x580, 7, false},  // TPDO2, RPDO2, SDO rx, tx
};

TEST(ConnectionSet, ShortSetsMapEveryServiceBothWays) {
  for (uint8_t i = 1; i < kConnectionSetCount; ++i) {
    const ConnectionSet s = connection_set_at(i);
    for (const Service& svc : kServices) {
      const uint8_t first = svc.node0 ? 0 : 1;
      const uint8_t last = svc.node0 ? 0 : s.max_nodes;
      for (uint16_t node = first; node <= last; ++node) {
        const uint16_t can = static_cast<uint16_t>(svc.can_base + node);
        uint16_t serial = 0xFFFF;
        ASSERT_EQ(can_to_serial(s, can, &serial), MapResult::kOk) << int(s.id_bits) << " " << can;
        EXPECT_EQ(serial, (svc.code << s.node_bits) | node);
        EXPECT_LT(serial, 1u << s.id_bits);
        EXPECT_EQ(function_code_of(s, serial), svc.code);
        EXPECT_EQ(node_id_of(s, serial), node);
        uint16_t back = 0xFFFF;
        ASSERT_EQ(serial_to_can(s, serial, &back), MapResult::kOk);
        EXPECT_EQ(back, can);
      }
    }
  }
}

TEST(ConnectionSet, EverySerialIdOfAShortSetMapsOrIsReserved) {
  for (uint8_t i = 1; i < kConnectionSetCount; ++i) {
    const ConnectionSet s = connection_set_at(i);
    int mapped = 0;
    for (uint16_t serial = 0; serial < (1u << s.id_bits); ++serial) {
      uint16_t can = 0;
      const MapResult r = serial_to_can(s, serial, &can);
      const bool reserved = node_id_of(s, serial) == 0 && function_code_of(s, serial) >= 3;
      EXPECT_EQ(r, reserved ? MapResult::kReservedCode : MapResult::kOk) << serial;
      if (r != MapResult::kOk) continue;
      ++mapped;
      uint16_t again = 0xFFFF;
      ASSERT_EQ(can_to_serial(s, can, &again), MapResult::kOk);
      EXPECT_EQ(again, serial) << "round trip of " << serial;
    }
    EXPECT_EQ(mapped, (1 << s.id_bits) - 5);  // 5 reserved codes with node id 0
    uint16_t can = 0;
    EXPECT_EQ(serial_to_can(s, static_cast<uint16_t>(1u << s.id_bits), &can), MapResult::kIdOutOfRange);
  }
}

TEST(ConnectionSet, ElevenBitSetIsTheIdentity) {
  const ConnectionSet s = connection_set(IdBits::k11);
  for (uint16_t can = 0; can < 0x800; ++can) {
    uint16_t serial = 0xFFFF, back = 0xFFFF;
    ASSERT_EQ(can_to_serial(s, can, &serial), MapResult::kOk);
    EXPECT_EQ(serial, can);
    ASSERT_EQ(serial_to_can(s, serial, &back), MapResult::kOk);
    EXPECT_EQ(back, can);
  }
  uint16_t out = 0;
  EXPECT_EQ(can_to_serial(s, 0x800, &out), MapResult::kIdOutOfRange);
  EXPECT_EQ(serial_to_can(s, 0x800, &out), MapResult::kIdOutOfRange);
}

TEST(ConnectionSet, ShortSetsRefuseWhatTheyCannotCarry) {
  const ConnectionSet s7 = connection_set(IdBits::k7);
  uint16_t out = 0x1234;
  // CAN functions without a 3-bit code: TPDO3/4, RPDO3/4, ids 001h-07Fh, LSS.
  for (int can : {0x385, 0x405, 0x485, 0x505, 0x001, 0x07F, 0x7E5, 0x7E4}) {
    EXPECT_EQ(can_to_serial(s7, static_cast<uint16_t>(can), &out), MapResult::kNoFunctionCode) << can;
  }
  // Node 0 with a per-node function (no such service): heartbeat 700h, TPDO1 180h.
  EXPECT_EQ(can_to_serial(s7, 0x700, &out), MapResult::kNoFunctionCode);
  EXPECT_EQ(can_to_serial(s7, 0x180, &out), MapResult::kNoFunctionCode);
  // Node ids beyond the set: 16 in the 7-bit set, 8 in the 6-bit, 32 in the 8-bit.
  EXPECT_EQ(can_to_serial(s7, 0x190, &out), MapResult::kNodeOutOfRange);
  EXPECT_EQ(can_to_serial(connection_set(IdBits::k6), 0x608, &out), MapResult::kNodeOutOfRange);
  EXPECT_EQ(can_to_serial(connection_set(IdBits::k8), 0x720, &out), MapResult::kNodeOutOfRange);
  EXPECT_EQ(can_to_serial(connection_set(IdBits::k8), 0x71F, &out), MapResult::kOk);
  EXPECT_EQ(can_to_serial(s7, 0x800, &out), MapResult::kIdOutOfRange);
  EXPECT_EQ(out, (0u << 5) | 31u) << "a refusal leaves the output alone";
}

TEST(ConnectionSet, ABridgesNodeOffsetMovesTheSegmentsNodesOnCan) {
  // A 7-bit segment seen on CAN at node ids 17..31 (offset 16), and a
  // 6-bit one at 121..127 (offset 120): every node, every service.
  const struct {
    IdBits bits;
    uint8_t offset;
  } cases[] = {{IdBits::k7, 16}, {IdBits::k6, 120}, {IdBits::k8, 96}, {IdBits::k11, 0}};
  for (const auto& c : cases) {
    const ConnectionSet s = connection_set(c.bits);
    for (const Service& svc : kServices) {
      if (svc.node0) {
        uint16_t serial = 0xFFFF, back = 0xFFFF;
        ASSERT_EQ(can_to_serial(s, svc.can_base, &serial, c.offset), MapResult::kOk);
        ASSERT_EQ(serial_to_can(s, serial, &back, c.offset), MapResult::kOk);
        EXPECT_EQ(back, svc.can_base) << "broadcasts keep node id 0";
        continue;
      }
      for (uint16_t node = 1; node <= s.max_nodes && node + c.offset <= 127u; ++node) {
        const uint16_t can = static_cast<uint16_t>(svc.can_base + node + c.offset);
        uint16_t serial = 0xFFFF, back = 0xFFFF;
        ASSERT_EQ(can_to_serial(s, can, &serial, c.offset), MapResult::kOk) << can;
        EXPECT_EQ(node_id_of(s, serial), node);
        ASSERT_EQ(serial_to_can(s, serial, &back, c.offset), MapResult::kOk);
        EXPECT_EQ(back, can);
      }
    }
  }
  const ConnectionSet s7 = connection_set(IdBits::k7);
  uint16_t out = 0;
  EXPECT_EQ(can_to_serial(s7, 0x190, &out, 16), MapResult::kNodeOutOfRange) << "node 16: below the segment";
  EXPECT_EQ(can_to_serial(s7, 0x1A0, &out, 16), MapResult::kNodeOutOfRange) << "node 32: beyond it";
  EXPECT_EQ(can_to_serial(s7, 0x191, &out, 16), MapResult::kOk);
  EXPECT_EQ(out, (2u << 4) | 1u);
  EXPECT_EQ(serial_to_can(s7, (2u << 4) | 15u, &out, 120), MapResult::kNodeOutOfRange) << "135 > 127";
}

TEST(ConnectionSet, DefaultSdoIds) {
  EXPECT_TRUE(is_default_sdo(0x581));
  EXPECT_TRUE(is_default_sdo(0x5FF));
  EXPECT_TRUE(is_default_sdo(0x601));
  EXPECT_TRUE(is_default_sdo(0x67F));
  EXPECT_FALSE(is_default_sdo(0x580));
  EXPECT_FALSE(is_default_sdo(0x600));
  EXPECT_FALSE(is_default_sdo(0x680));
  EXPECT_FALSE(is_default_sdo(0x185));
}

}  // namespace
}  // namespace serialnet
}  // namespace mb2co
