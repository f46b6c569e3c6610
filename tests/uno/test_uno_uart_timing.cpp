// USART0 at the rate the image sets (hil/uno/uno_board.h, "USART0 timing"):
// the gateway image writes UBRR0 = 16 before it sets U2X0, which on the chip
// is 117.6 kbaud (115200 within 2.1 %), 10 bits a character in 8N1: 85 µs.
// simavr 1.6 alone took U2X0 as it stood at the UBRR0L write (clear) and
// counted a parity bit: 187 µs a character, every Modbus answer twice its
// wire time. Shown here in UnoRig on the real image, timed in its own clock.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "crc/crc16.h"
#include "uno_rig.h"

namespace mb2co {
namespace uno {
namespace {

constexpr uint64_t kCharCycles = 17u * 8u * 10u;  // (UBRR0 + 1) * 8 clocks a bit (U2X0), 10 bits

TEST(UnoUart, CharacterTimeIsTheOneTheImageSets) {
  UnoRig rig;
  const Status loaded = rig.load(MB2CO_UNO_GATEWAY_ELF);
  ASSERT_TRUE(loaded) << loaded.message();
  ASSERT_TRUE(rig.run_until_us(50000));  // past uart_begin()
  EXPECT_EQ(rig.board().uart_cycles_per_char(), kCharCycles);
}

TEST(UnoUart, AnAnswerLeavesAtTheLineRate) {
  UnoRig rig;
  ASSERT_TRUE(rig.load(MB2CO_UNO_GATEWAY_ELF));
  uint64_t t = 0;
  while (!rig.modbus_ready() && t < 2000000) ASSERT_TRUE(rig.run_until_us(t += 100));
  ASSERT_TRUE(rig.modbus_ready());
  // FC 04, input registers 0..22 of slave 1: 5 + 46 bytes back.
  std::vector<uint8_t> req = {1, 4, 0, 0, 0, 23};
  const uint16_t crc = crc16(req.data(), static_cast<uint16_t>(req.size()));
  req.push_back(static_cast<uint8_t>(crc & 0xFF));
  req.push_back(static_cast<uint8_t>(crc >> 8));
  rig.serial_in(req.data(), req.size());
  const uint64_t sent_us = rig.now_us();
  std::string answer;
  uint64_t first_us = 0, last_us = 0;
  for (t = sent_us; t < sent_us + 50000 && answer.size() < 51; t += 10) {  // 10 µs steps
    ASSERT_TRUE(rig.run_until_us(t));
    const std::string out = rig.take_serial_out();
    if (out.empty()) continue;
    if (answer.empty()) first_us = rig.now_us();
    last_us = rig.now_us();
    answer += out;
  }
  ASSERT_EQ(answer.size(), 51u);
  EXPECT_EQ(static_cast<uint8_t>(answer[1]), 4u);
  // A byte is handed out when the image writes it to UDR0, one character
  // time after the one before: 50 gaps of 85 µs (187 µs before the fix).
  const uint64_t span_us = last_us - first_us;
  const uint64_t want_us = 50u * kCharCycles / 16u;
  EXPECT_NEAR(static_cast<double>(span_us), static_cast<double>(want_us), 30.0);
  // The request itself takes 8 characters to arrive, then t3.5 of silence
  // (1750 µs) before the image may answer: the first byte not before that.
  EXPECT_GE(first_us - sent_us, 8u * kCharCycles / 16u + 1750u);
  printf("answer: first byte %llu us after the request was handed in, 51 bytes in %llu us\n",
         static_cast<unsigned long long>(first_us - sent_us), static_cast<unsigned long long>(span_us));
}

}  // namespace
}  // namespace uno
}  // namespace mb2co
