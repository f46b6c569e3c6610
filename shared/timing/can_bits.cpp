#include "timing/can_bits.h"

namespace mb2co {
namespace timing {
namespace {

// Fixed parts of the frame, in bits. Standard: SOF 1, ID 11, RTR 1, IDE 1,
// r0 1, DLC 4. Extended: SOF 1, base ID 11, SRR 1, IDE 1, ID extension 18,
// RTR 1, r1 1, r0 1, DLC 4.
constexpr uint16_t kHeaderStandardBits = 19;
constexpr uint16_t kHeaderExtendedBits = 39;
constexpr uint16_t kCrcBits = 15;
// CRC delimiter 1, ACK slot 1, ACK delimiter 1, EOF 7, interframe space 3.
constexpr uint16_t kTrailerBits = 13;
constexpr uint16_t kCrcPolynomial = 0x4599;

// Counts stuff bits as a CAN controller inserts them: after five equal bits a
// complement bit is sent, and that bit starts the next run.
struct StuffCounter {
  uint16_t bits = 0;
  uint16_t stuff = 0;
  uint8_t run = 0;
  bool last = false;

  void push(bool bit) {
    ++bits;
    if (run != 0 && bit == last) {
      ++run;
    } else {
      last = bit;
      run = 1;
    }
    if (run == 5) {
      ++stuff;
      last = !last;
      run = 1;
    }
  }
};

// Feeds the stuffing counter and the CRC with the bits of the frame from SOF
// to the end of the data field, most significant bit first.
struct FrameEncoder {
  StuffCounter stuffing;
  uint16_t crc = 0;

  void push(bool bit) {
    stuffing.push(bit);
    crc = crc15_update(crc, bit);
  }
  void push_field(uint32_t value, uint8_t width) {
    for (uint8_t i = width; i > 0; --i) push(((value >> (i - 1)) & 1u) != 0);
  }
};

}  // namespace

uint16_t crc15_update(uint16_t crc, bool bit) {
  const bool feedback = bit != (((crc >> 14) & 1u) != 0);
  crc = static_cast<uint16_t>((static_cast<uint32_t>(crc) << 1) & 0x7FFFu);
  if (feedback) crc = static_cast<uint16_t>(crc ^ kCrcPolynomial);
  return crc;
}

uint16_t stuffable_bits(bool extended, uint8_t dlc) {
  const uint16_t header = extended ? kHeaderExtendedBits : kHeaderStandardBits;
  return static_cast<uint16_t>(header + 8u * dlc_bytes(dlc) + kCrcBits);
}

uint16_t frame_bits_unstuffed(bool extended, uint8_t dlc) {
  return static_cast<uint16_t>(stuffable_bits(extended, dlc) + kTrailerBits);
}

uint16_t worst_stuff_bits(bool extended, uint8_t dlc, WorstCase convention) {
  const uint16_t g = stuffable_bits(extended, dlc);
  if (convention == WorstCase::kCourse) {
    // The seed counts the CRC field as 16 bits (delimiter included): 99 bits
    // for 8 bytes, 19 stuff bits.
    return static_cast<uint16_t>((g + 1u) / 5u);
  }
  return static_cast<uint16_t>((g - 1u) / 4u);
}

uint16_t frame_bits_worst(bool extended, uint8_t dlc, WorstCase convention) {
  return static_cast<uint16_t>(frame_bits_unstuffed(extended, dlc) +
                               worst_stuff_bits(extended, dlc, convention));
}

ExactFrameBits frame_bits_exact(const CanFrame& frame) {
  FrameEncoder enc;
  const bool rtr = frame.rtr();
  enc.push(false);  // SOF, dominant
  if (frame.extended()) {
    const uint32_t id = frame.id & 0x1FFFFFFFu;
    enc.push_field(id >> 18, 11);
    enc.push(true);  // SRR, recessive
    enc.push(true);  // IDE, recessive: extended
    enc.push_field(id & 0x3FFFFu, 18);
    enc.push(rtr);
    enc.push(false);  // r1
    enc.push(false);  // r0
  } else {
    enc.push_field(frame.id & 0x7FFu, 11);
    enc.push(rtr);
    enc.push(false);  // IDE, dominant: standard
    enc.push(false);  // r0
  }
  enc.push_field(frame.dlc & 0x0Fu, 4);
  const uint8_t bytes = rtr ? uint8_t{0} : dlc_bytes(frame.dlc);
  for (uint8_t i = 0; i < bytes; ++i) enc.push_field(frame.data[i], 8);
  const uint16_t crc = enc.crc;
  for (uint8_t i = kCrcBits; i > 0; --i) enc.stuffing.push(((crc >> (i - 1)) & 1u) != 0);

  ExactFrameBits out;
  out.stuff_bits = enc.stuffing.stuff;
  out.total_bits = static_cast<uint16_t>(enc.stuffing.bits + enc.stuffing.stuff + kTrailerBits);
  out.crc15 = crc;
  return out;
}

}  // namespace timing
}  // namespace mb2co
