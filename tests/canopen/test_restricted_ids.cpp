// CiA 301 §7.3.5: the CAN-IDs no PDO, EMCY or SYNC COB-ID may use, checked
// for every 11-bit id (and beyond) against the table of the standard.
#include <gtest/gtest.h>
#include <stdint.h>

#include "canopen/pdo_map.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

// The restricted blocks as CiA 301 lists them: NMT, reserved, SYNC/EMCY/TIME
// area up to 180h, SDO responses, SDO requests, reserved (6E0h..6FFh), NMT
// error control.
bool restricted_by_the_table(uint32_t id) {
  struct Block {
    uint32_t first, last;
  };
  const Block blocks[] = {{0x000, 0x000}, {0x001, 0x07F}, {0x101, 0x180}, {0x581, 0x5FF},
                          {0x601, 0x67F}, {0x6E0, 0x6FF}, {0x701, 0x7FF}};
  for (const Block& b : blocks) {
    if (id >= b.first && id <= b.last) return true;
  }
  return false;
}

TEST(RestrictedCanIds, EveryElevenBitIdAsTheStandardLists) {
  for (uint32_t id = 0; id <= 0x7FF; ++id) {
    EXPECT_EQ(can_id_restricted(id), restricted_by_the_table(id)) << std::hex << id;
  }
}

TEST(RestrictedCanIds, BlockEdges) {
  for (uint32_t id :
       {0x000u, 0x07Fu, 0x101u, 0x180u, 0x581u, 0x5FFu, 0x601u, 0x67Fu, 0x6E0u, 0x6FFu, 0x701u, 0x7FFu}) {
    EXPECT_TRUE(can_id_restricted(id)) << std::hex << id;
  }
  for (uint32_t id : {0x080u, 0x100u, 0x181u, 0x580u, 0x600u, 0x680u, 0x6DFu, 0x700u}) {
    EXPECT_FALSE(can_id_restricted(id)) << std::hex << id;
  }
}

TEST(RestrictedCanIds, ValuesBeyondElevenBitsAreNotInTheTable) {
  // Callers mask to 11 bits; beyond them no block matches.
  for (uint32_t id : {0x800u, 0x801u, 0x1000u, 0x10701u, 0x1FFFFFFFu, 0xFFFFFFFFu}) {
    EXPECT_FALSE(can_id_restricted(id)) << std::hex << id;
  }
}

}  // namespace
}  // namespace test
}  // namespace mb2co
