// mb2co-lab's sync-processing (seed 000 §5.1) on the real gateway image in
// simavr: the cycle count comes from the image itself and lies within the
// simulator's pass-time bound. Needs the AVR images (mb2co-avr-images).
#include <gtest/gtest.h>

#include "sync_processing.h"

namespace mb2co {
namespace lab {
namespace {

TEST(SyncProcessing, RealImageAnswersEverySyncWithinTheBound) {
  const SyncProcessingResult r = sync_processing_run(MB2CO_GATEWAY_ELF, 40, 1);
  ASSERT_EQ(r.error, "");
  EXPECT_EQ(r.node_id, 1u);  // the image's default node id (erased EEPROM)
  ASSERT_EQ(r.cycles.size(), 40u);
  // Noticing the SYNC (INT, reading RXB over SPI at 1 µs a byte) and building
  // the PDO take real work: far more than a few hundred cycles, and they
  // depend on where the main loop was, so they spread.
  EXPECT_GT(r.min_cycles, 1600u);
  EXPECT_GT(r.max_cycles, r.min_cycles);
  EXPECT_LE(r.max_cycles, r.bound_us * 16u);
  EXPECT_TRUE(r.ok);
}

TEST(SyncProcessing, AMissingImageIsReportedNotMeasured) {
  const SyncProcessingResult r = sync_processing_run("/nonexistent/mb2co-gateway.elf", 5, 1);
  EXPECT_NE(r.error, "");
  EXPECT_TRUE(r.cycles.empty());
  EXPECT_FALSE(r.ok);
}

}  // namespace
}  // namespace lab
}  // namespace mb2co
