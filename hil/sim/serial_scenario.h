// The serial segment scenario (issue 13, seed 003): real I/O nodes on one
// simulated multi-drop line, polled by one SYNC producer or passing the
// token, each node's input published by its TPDO1 and consumed by the next
// node's RPDO1, inputs changing at random moments, for a given number of
// cycles; optionally one node unplugged halfway. Every TPDO's latency (from
// the moment its node core queued it to the end of its last byte on the
// line) is measured against the bound of shared/timing/serial_segment.h,
// the cycle (node 1's window start to the next) against the cycle bound,
// and every silence on the line against the token's recovery bound.
#pragma once
#include <stdint.h>

#include "serialnet/connection_set.h"

namespace mb2co {
namespace sim {

struct SerialScenarioConfig {
  serialnet::IdBits bits = serialnet::IdBits::k7;
  uint8_t nodes = 15;  ///< node ids 1..nodes; node 1 polls or starts the token
  bool token = false;  ///< token passing, else polling
  uint32_t baud = 115200;
  uint32_t window_us = 3600;  ///< W of every node
  uint32_t guard_us = 100;    ///< G
  uint32_t cycles = 10000;    ///< run until node 1 got this many windows
  uint8_t remove_node = 0;    ///< unplugged at cycles / 2 (0: none; not node 1),
                              ///< with token passing while it holds the token
  uint16_t heartbeat_ms = 1000;
  uint32_t seed = 1;
};

struct SerialScenarioResult {
  uint32_t cycles = 0;                ///< node 1's windows during the measurement
  uint64_t messages = 0;              ///< on the line, SYNCs included
  uint64_t pdos = 0;                  ///< TPDOs measured
  uint64_t pdos_late = 0;             ///< above their bound
  uint32_t pdo_bound_us = 0;          ///< all nodes present
  uint32_t pdo_bound_missing_us = 0;  ///< after the removal (token passing: one T_recover more)
  uint32_t pdo_max_us = 0;            ///< the longest measured
  uint64_t pdo_sum_us = 0;            ///< for the mean
  uint32_t cycle_bound_us = 0;        ///< poll cycle or token round (all present)
  uint32_t cycle_bound_missing_us = 0;
  uint32_t cycle_max_us = 0;           ///< before the removal
  uint32_t cycle_max_missing_us = 0;   ///< after it
  uint64_t cycle_sum_us = 0;           ///< over cycles
  uint32_t recovery_bound_us = 0;      ///< T_recover
  uint32_t silence_max_us = 0;         ///< longest end-to-end gap on the line after the removal
  uint32_t recoveries = 0;             ///< the starter's count
  bool removed_holding_token = false;  ///< token passing: the node went while it held the token
  uint32_t unexpected = 0;             ///< EMCY or SDO messages (the bound assumes none ahead of a TPDO)
  uint32_t outputs_wrong = 0;          ///< consumers whose output is not the producer's last input at the end
  uint32_t decode_errors = 0;          ///< CRC, length, truncation errors seen by any node
  int collisions = 0;
  uint64_t events_us = 0;  ///< simulated time of the measurement
  bool ok = false;         ///< nothing late, no collision, no error, outputs right, recovery in bound
};

SerialScenarioResult serial_scenario(const SerialScenarioConfig& c);

}  // namespace sim
}  // namespace mb2co
