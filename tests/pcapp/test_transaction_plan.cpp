#include <gtest/gtest.h>

#include "canopen/od.h"
#include "gateway/gateway_od.h"
#include "timing/rtu_timing.h"
#include "transaction_plan.h"

using mb2co::Status;
using namespace mb2co::pcapp;

namespace {
const std::vector<Field> kStationReads = {Field::kInputs,     Field::kRunState, Field::kStop2Count,
                                          Field::kStopCause,  Field::kPrevRun,  Field::kPrevStop2,
                                          Field::kPrevStatus, Field::kNextRun,  Field::kNextStatus};

/// The gateway OD with the holding map replaced by `entries` (PDO mapping format).
RegisterLayout layout_with_holding_map(const std::vector<uint32_t>& entries) {
  static mb2co::gateway::od::GatewayValues values;
  mb2co::canopen::ObjectDictionary od(mb2co::gateway::od::GatewayDefinition,
                                      reinterpret_cast<uint8_t*>(&values));
  od.restore_defaults(0x0000, 0xFFFF);
  const uint16_t row0 = od.find(0x2400, 0);
  od.set(row0, static_cast<uint32_t>(entries.size()));
  for (size_t i = 0; i < entries.size(); ++i) od.set(static_cast<uint16_t>(row0 + 1 + i), entries[i]);
  return layout_from_od(od);
}
uint32_t map(uint16_t index, uint8_t sub, uint8_t bits) {
  return uint32_t{index} << 16 | uint32_t{sub} << 8 | bits;
}
}  // namespace

TEST(TransactionPlan, DefaultMapStationIsOneInputReadAndOneWrite) {
  TransactionPlan p;
  ASSERT_TRUE(
      plan_transactions(default_layout(), kStationReads, {Field::kNmtState}, {Field::kRunCommand}, p));
  EXPECT_FALSE(p.read_write);  // the inputs are input registers: FC 17h cannot read them
  EXPECT_EQ(describe(p), "FC 04 IR 0-22 + FC 06 HR 0");
  EXPECT_EQ(transaction_count(p), 2u);
}

TEST(TransactionPlan, LatencyReadsOnlyUpToTheLedStamp) {
  TransactionPlan p;
  ASSERT_TRUE(plan_transactions(default_layout(),
                                {Field::kInputs, Field::kEdgeUs, Field::kLedUs, Field::kLeds}, {},
                                {Field::kLabLed}, p));
  EXPECT_EQ(describe(p), "FC 04 IR 0-15 + FC 06 HR 1");
}

TEST(TransactionPlan, WireTimeIsTheSumOfTheFramesAndSilences) {
  TransactionPlan p;
  ASSERT_TRUE(
      plan_transactions(default_layout(), kStationReads, {Field::kNmtState}, {Field::kRunCommand}, p));
  mb2co::timing::SerialFormat f;
  f.parity = mb2co::modbus::Parity::kNone;  // 8N1: 10 bits a character
  // FC 04 of 23 registers: 8 + 51 bytes; FC 06: 8 + 8 bytes; 75 characters.
  const uint64_t ns_per_bit_x = 1000000000ull;  // frames are floored one by one
  EXPECT_EQ(plan_frame_time_ns(p, f),
            80 * ns_per_bit_x / 115200 + 510 * ns_per_bit_x / 115200 + 2 * (80 * ns_per_bit_x / 115200));
  EXPECT_EQ(plan_frame_time_ns(p, f), 6510415u);
  EXPECT_EQ(plan_wire_time_ns(p, f), plan_frame_time_ns(p, f) + 2u * 1750000u);
}

// mb2co-plant's response timeout follows the line (issue 27): the longest
// exchange (here FC 04 of 23 registers, 8 + 51 bytes) on the wire, the
// slave's t3.5, the gateway's reply time and the host margin.
TEST(TransactionPlan, ResponseTimeoutIsDerivedFromTheBaudRateAndTheReplyTime) {
  TransactionPlan p;
  ASSERT_TRUE(
      plan_transactions(default_layout(), kStationReads, {Field::kNmtState}, {Field::kRunCommand}, p));
  mb2co::timing::SerialFormat f;
  f.parity = mb2co::modbus::Parity::kNone;  // 8N1: 10 bits a character
  // 59 characters of 10 bits at 115200: 5,122 µs (each frame rounded up),
  // t3.5 1,750 µs, reply 4,000 µs, margin 25,000 µs: 35,872 µs → 36 ms.
  EXPECT_EQ(derived_timeout_ms(p, &f), 36);
  // At 9600 baud the frames alone are 61.5 ms (the old fixed 25 ms never
  // waited long enough): 590 bits + t3.5 of 3.5 characters (3,646 µs) + 4 +
  // 25 ms = 94,104 µs.
  f.baud = 9600;
  EXPECT_EQ(derived_timeout_ms(p, &f), 95);
  // 8E1 at 9600: 11 bits a character, 67.6 ms of frames, t3.5 4,011 µs.
  f.parity = mb2co::modbus::Parity::kEven;
  EXPECT_EQ(derived_timeout_ms(p, &f), 101);
  // Modbus/TCP: no wire, the reply time and the margin.
  EXPECT_EQ(derived_timeout_ms(p, nullptr), 29);
  // FC 2B/0E (7 + 48 characters) is longer than a cycle of FC 04 of one
  // register (8 + 7, which alone would give 33 ms): 4,775 µs + 1,750 +
  // 4,000 + 25,000 = 35,525 µs.
  TransactionPlan one;
  ASSERT_TRUE(plan_transactions(default_layout(), {Field::kRunState}, {}, {}, one));
  f.baud = 115200;
  f.parity = mb2co::modbus::Parity::kNone;
  EXPECT_EQ(derived_timeout_ms(one, &f), 36);
}

TEST(TransactionPlan, ReadWriteWhenTheHoldingMapHoldsEverything) {
  // A map that puts RUN command and the station's inputs in holding registers.
  std::vector<uint32_t> entries = {
      map(0x2100, 1, 8), map(0x6000, 1, 8),  map(0x2100, 2, 8), map(0x2100, 3, 16), map(0x2100, 4, 8),
      map(0x2110, 1, 8), map(0x2110, 2, 16), map(0x2110, 3, 8), map(0x2120, 1, 8),  map(0x2120, 3, 8)};
  const RegisterLayout l = layout_with_holding_map(entries);
  TransactionPlan p;
  const Status status = plan_transactions(l, kStationReads, {}, {Field::kRunCommand}, p);
  ASSERT_TRUE(status) << status.message();
  EXPECT_TRUE(p.read_write);
  EXPECT_EQ(describe(p), "FC 17 write HR 0 read HR 1-9");
  EXPECT_EQ(transaction_count(p), 1u);
}

TEST(TransactionPlan, UnmappedHoleSplitsTheRead) {
  std::vector<uint32_t> entries = {map(0x2100, 1, 8), map(0x6000, 1, 8), 0, map(0x2100, 2, 8)};
  const RegisterLayout l = layout_with_holding_map(entries);
  TransactionPlan p;
  ASSERT_TRUE(plan_transactions(l, {Field::kInputs, Field::kRunState}, {}, {Field::kRunCommand}, p));
  EXPECT_FALSE(p.read_write);
  EXPECT_EQ(describe(p), "FC 03 HR 1 + FC 03 HR 3 + FC 06 HR 0");
}

TEST(TransactionPlan, MissingRequiredFieldIsAnError) {
  std::vector<uint32_t> entries = {map(0x2100, 1, 8)};
  RegisterLayout l = layout_with_holding_map(entries);
  l.at[static_cast<int>(Field::kInputs)] = Location{};
  TransactionPlan p;
  const Status status = plan_transactions(l, {Field::kInputs}, {}, {Field::kRunCommand}, p);
  EXPECT_FALSE(status);
  EXPECT_EQ(status.message(), "the gateway's register map has no inputs (6000h/01)");
}

TEST(TransactionPlan, WriteToAnInputRegisterIsRefused) {
  TransactionPlan p;
  const Status status = plan_transactions(default_layout(), {Field::kInputs}, {}, {Field::kRunState}, p);
  EXPECT_FALSE(status);
  EXPECT_NE(status.message().find("no writable holding register for run_state"), std::string::npos);
}
