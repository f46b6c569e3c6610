// CAN bit timing of the MCP2515 with the 16 MHz crystal of the SparkFun
// CAN-BUS shield, as CNF1..CNF3 register values computed from segment lengths.
//
// One time quantum TQ = 2 * (BRP + 1) / 16 MHz. A bit is
//   SyncSeg (1 TQ) + PropSeg + PS1 | sample point | PS2
// Datasheet rules (checked below): PropSeg + PS1 >= PS2, PS2 > SJW, PS2 >= 2,
// each segment 1..8 TQ, 8..25 TQ per bit. CiA 301 recommends a sample point
// of 87.5 % up to 800 kbit/s and 75 % at 1 Mbit/s.
//
//  rate      BRP  TQ      TQ/bit  Prop PS1 PS2 SJW  sample   CNF1 CNF2 CNF3
//  1000 k     0   125 ns     8     3    2   2   1    75.0 %  0x00 0x8A 0x01
//   500 k     0   125 ns    16     5    8   2   1    87.5 %  0x00 0xBC 0x01
//   250 k     1   250 ns    16     5    8   2   1    87.5 %  0x01 0xBC 0x01
//   125 k     3   500 ns    16     5    8   2   1    87.5 %  0x03 0xBC 0x01
// At 1 Mbit/s 8 TQ leave no room for 87.5 % (PS2 cannot go below 2 TQ).
// PropSeg of 5 TQ (625 ns and more) covers two transceiver delays and a
// few metres of cable; at 1 Mbit/s 375 ns keeps the bus short (< ~10 m).
#pragma once
#include <stdint.h>

namespace mb2co {
namespace mcp2515 {

enum class Bitrate : uint8_t { k125k, k250k, k500k, k1000k };

constexpr uint32_t kOscillatorHz = 16000000u;

/// Segment lengths in time quanta (SyncSeg is always 1 TQ).
struct BitTiming {
  uint8_t brp;      ///< baud rate prescaler 0..63: TQ = 2 * (brp + 1) / fosc
  uint8_t prop_tq;  ///< 1..8
  uint8_t ps1_tq;   ///< 1..8
  uint8_t ps2_tq;   ///< 2..8
  uint8_t sjw_tq;   ///< 1..4, < ps2_tq
};

constexpr uint8_t total_tq(const BitTiming& t) {
  return static_cast<uint8_t>(1u + t.prop_tq + t.ps1_tq + t.ps2_tq);
}
constexpr uint32_t bitrate_bps(const BitTiming& t) {
  return kOscillatorHz / (2u * (static_cast<uint32_t>(t.brp) + 1u) * total_tq(t));
}
/// Sample point in per mille of the bit time.
constexpr uint16_t sample_point_permille(const BitTiming& t) {
  return static_cast<uint16_t>(1000u * (1u + t.prop_tq + t.ps1_tq) / total_tq(t));
}
constexpr bool valid(const BitTiming& t) {
  return t.brp <= 63 && t.prop_tq >= 1 && t.prop_tq <= 8 && t.ps1_tq >= 1 && t.ps1_tq <= 8 && t.ps2_tq >= 2 &&
         t.ps2_tq <= 8 && t.sjw_tq >= 1 && t.sjw_tq <= 4 && t.sjw_tq < t.ps2_tq &&
         t.prop_tq + t.ps1_tq >= t.ps2_tq && total_tq(t) >= 8 && total_tq(t) <= 25;
}

/// CNF1: SJW-1 in bits 7:6, BRP in 5:0.
constexpr uint8_t cnf1(const BitTiming& t) {
  return static_cast<uint8_t>(((t.sjw_tq - 1u) << 6) | t.brp);
}
/// CNF2: BTLMODE=1 (PS2 from CNF3), SAM=0 (one sample), PS1-1 in 5:3, PropSeg-1 in 2:0.
constexpr uint8_t cnf2(const BitTiming& t) {
  return static_cast<uint8_t>(0x80u | ((t.ps1_tq - 1u) << 3) | (t.prop_tq - 1u));
}
/// CNF3: SOF=0 (CLKOUT pin as clock, unused), WAKFIL=0, PS2-1 in 2:0.
constexpr uint8_t cnf3(const BitTiming& t) {
  return static_cast<uint8_t>(t.ps2_tq - 1u);
}

constexpr BitTiming kTiming1000k{0, 3, 2, 2, 1};
constexpr BitTiming kTiming500k{0, 5, 8, 2, 1};
constexpr BitTiming kTiming250k{1, 5, 8, 2, 1};
constexpr BitTiming kTiming125k{3, 5, 8, 2, 1};

static_assert(valid(kTiming1000k) && bitrate_bps(kTiming1000k) == 1000000u &&
                  sample_point_permille(kTiming1000k) == 750,
              "1 Mbit/s timing");
static_assert(valid(kTiming500k) && bitrate_bps(kTiming500k) == 500000u &&
                  sample_point_permille(kTiming500k) == 875,
              "500 kbit/s timing");
static_assert(valid(kTiming250k) && bitrate_bps(kTiming250k) == 250000u &&
                  sample_point_permille(kTiming250k) == 875,
              "250 kbit/s timing");
static_assert(valid(kTiming125k) && bitrate_bps(kTiming125k) == 125000u &&
                  sample_point_permille(kTiming125k) == 875,
              "125 kbit/s timing");
static_assert(cnf1(kTiming500k) == 0x00 && cnf2(kTiming500k) == 0xBC && cnf3(kTiming500k) == 0x01,
              "table in the header comment");
static_assert(cnf2(kTiming1000k) == 0x8A && cnf1(kTiming125k) == 0x03, "table in the header comment");

/// CNF3 | CNF2 << 8 | CNF1 << 16: the three registers in address order.
constexpr uint32_t cnf_bytes(const BitTiming& t) {
  return cnf3(t) | (static_cast<uint32_t>(cnf2(t)) << 8) | (static_cast<uint32_t>(cnf1(t)) << 16);
}

constexpr BitTiming timing_for(Bitrate rate) {
  return rate == Bitrate::k1000k  ? kTiming1000k
         : rate == Bitrate::k500k ? kTiming500k
         : rate == Bitrate::k250k ? kTiming250k
                                  : kTiming125k;
}

/// Bits per second of `rate` (for bus-off recovery time, timing analysis).
constexpr uint32_t bits_per_second(Bitrate rate) {
  return bitrate_bps(timing_for(rate));
}

}  // namespace mcp2515
}  // namespace mb2co
