// Issue 13's check in the simulator: 15 real I/O nodes on one 7-bit serial
// segment, polling and token passing, every TPDO on the line within its
// computed bound (shared/timing/serial_segment.h) over many cycles; a node
// unplugged halfway, and the token recovers within T_recover.
// MB2CO_SERIAL_CYCLES overrides the cycle count (default below).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>

#include "sim/serial_scenario.h"

namespace mb2co {
namespace sim {
namespace {

uint32_t cycles() {
  const char* env = std::getenv("MB2CO_SERIAL_CYCLES");
  return env != nullptr ? static_cast<uint32_t>(std::strtoul(env, nullptr, 10)) : 10000u;
}

void expect_within_bounds(const SerialScenarioConfig& c, const SerialScenarioResult& r) {
  EXPECT_GE(r.cycles, c.cycles);
  EXPECT_GE(r.pdos, uint64_t{c.cycles} * c.nodes / 2) << "about one change per node and cycle";
  EXPECT_EQ(r.pdos_late, 0u) << "longest " << r.pdo_max_us << " µs, bound " << r.pdo_bound_us;
  EXPECT_LE(r.pdo_max_us, r.pdo_bound_missing_us);
  EXPECT_LE(r.cycle_max_us, r.cycle_bound_us);
  EXPECT_EQ(r.collisions, 0);
  EXPECT_EQ(r.decode_errors, 0u);
  EXPECT_EQ(r.unexpected, 0u);
  EXPECT_EQ(r.outputs_wrong, 0u) << "every consumer shows its producer's last input";
  EXPECT_TRUE(r.ok);
  std::printf(
      "%u nodes, %s: %u cycles, %llu messages, %llu TPDOs: longest %u µs (bound %u), mean %llu µs; "
      "cycle max %u µs (bound %u), mean %llu µs\n",
      c.nodes, c.token ? "token" : "polling", r.cycles, static_cast<unsigned long long>(r.messages),
      static_cast<unsigned long long>(r.pdos), r.pdo_max_us, r.pdo_bound_us,
      static_cast<unsigned long long>(r.pdo_sum_us / (r.pdos ? r.pdos : 1)), r.cycle_max_us, r.cycle_bound_us,
      static_cast<unsigned long long>(r.cycle_sum_us / (r.cycles ? r.cycles : 1)));
}

TEST(SerialSegment, FifteenNodesPolledEveryPdoWithinItsBound) {
  SerialScenarioConfig c;
  c.cycles = cycles();
  c.remove_node = 9;  // its window stays silent: nothing else changes
  const SerialScenarioResult r = serial_scenario(c);
  expect_within_bounds(c, r);
  EXPECT_EQ(r.recoveries, 0u);
  EXPECT_LE(r.cycle_max_missing_us, r.cycle_bound_us) << "polling's cycle does not grow";
  // The bound is not loose by an order of magnitude: some PDO waited most of a cycle.
  EXPECT_GT(r.pdo_max_us, r.cycle_bound_us / 2);
}

TEST(SerialSegment, FifteenNodesPassingTheTokenOneRemovedMidRun) {
  SerialScenarioConfig c;
  c.token = true;
  c.cycles = cycles();
  c.remove_node = 9;
  const SerialScenarioResult r = serial_scenario(c);
  expect_within_bounds(c, r);
  EXPECT_TRUE(r.removed_holding_token) << "the token died with the node";
  // The removed node costs one recovery per round, each within T_recover.
  EXPECT_GE(r.recoveries, c.cycles / 2 - 1);
  EXPECT_GT(r.silence_max_us, c.window_us) << "a recovery was measured";
  EXPECT_LE(r.silence_max_us, r.recovery_bound_us);
  EXPECT_LE(r.cycle_max_missing_us, r.cycle_bound_missing_us);
  std::printf(
      "token recovery: %u recoveries, longest silence %u µs (T_recover %u), round max %u µs (bound %u)\n",
      r.recoveries, r.silence_max_us, r.recovery_bound_us, r.cycle_max_missing_us, r.cycle_bound_missing_us);
}

// The other sizes of docs/serial-canopen.md: 4 nodes (7-bit) and 31 nodes
// (8-bit), both access methods, a shorter run each.
TEST(SerialSegment, FourAndThirtyOneNodesWithinTheirBounds) {
  for (const uint8_t nodes : {uint8_t{4}, uint8_t{31}}) {
    for (const bool token : {false, true}) {
      SerialScenarioConfig c;
      c.nodes = nodes;
      c.bits = nodes > 15 ? serialnet::IdBits::k8 : serialnet::IdBits::k7;
      c.token = token;
      c.cycles = std::min(cycles(), 1000u);
      const SerialScenarioResult r = serial_scenario(c);
      SCOPED_TRACE(std::to_string(nodes) + (token ? " nodes, token" : " nodes, polling"));
      expect_within_bounds(c, r);
    }
  }
}

}  // namespace
}  // namespace sim
}  // namespace mb2co
