// The serial message format: round trips in every connection set, stuffing,
// and a receiver that survives noise: random bytes between messages, a
// flipped bit, cut messages, and resynchronises at the next flag.
#include <gtest/gtest.h>
#include <string.h>

#include <random>
#include <vector>

#include "crc/crc16.h"
#include "serialnet/frame_codec.h"

namespace mb2co {
namespace serialnet {
namespace {

using Bytes = std::vector<uint8_t>;

Bytes encoded(const ConnectionSet& set, const SerialMessage& m) {
  uint8_t buf[kMaxEncodedBytes];
  const uint8_t n = encode(set, m, buf, sizeof buf);
  return Bytes(buf, buf + n);
}

SerialMessage msg(uint16_t id, std::initializer_list<uint8_t> data) {
  SerialMessage m = {};
  m.id = id;
  for (uint8_t b : data) m.data[m.length++] = b;
  return m;
}

// Feeds bytes 87 µs apart (115200 baud); returns the messages decoded.
struct Feed {
  explicit Feed(const ConnectionSet& set, uint32_t gap_us = 0) : dec(set, gap_us) {}
  Decoder dec;
  uint32_t t = 1000;
  std::vector<SerialMessage> got;
  std::vector<Decoder::Result> results;
  void bytes(const Bytes& b, uint32_t step_us = 87) {
    for (uint8_t x : b) {
      t += step_us;
      const Decoder::Result r = dec.push(x, t);
      if (r == Decoder::kMessage) got.push_back(dec.message());
      if (r != Decoder::kNothing) results.push_back(r);
    }
  }
};

bool same(const SerialMessage& a, const SerialMessage& b) {
  return a.id == b.id && a.length == b.length && memcmp(a.data, b.data, a.length) == 0;
}

TEST(FrameCodec, LayoutIsFlagIdLengthDataCrcLowFirst) {
  const ConnectionSet s7 = connection_set(IdBits::k7);
  const Bytes b = encoded(s7, msg(0x25, {0x11, 0x22}));
  uint8_t content[] = {0x25, 0x02, 0x11, 0x22, 0, 0};
  append_crc(content, 4);
  const Bytes want = {kFlag, 0x25, 0x02, 0x11, 0x22, content[4], content[5]};
  EXPECT_EQ(b, want);
  // 11-bit set: two id bytes, high first.
  const Bytes b11 = encoded(connection_set(IdBits::k11), msg(0x605, {}));
  ASSERT_GE(b11.size(), 5u);
  EXPECT_EQ(b11[1], 0x06);
  EXPECT_EQ(b11[2], 0x05);
  EXPECT_EQ(b11[3], 0x00);
  EXPECT_EQ(b11.size(), 6u);
}

TEST(FrameCodec, StuffsFlagAndEscapeAndNeverSendsAFlagInside) {
  const ConnectionSet s8 = connection_set(IdBits::k8);
  const Bytes b = encoded(s8, msg(0x7E, {0x7E, 0x7D, 0x00, 0x20, 0x5E}));
  EXPECT_EQ(b[0], kFlag);
  EXPECT_EQ(b[1], kEscape);
  EXPECT_EQ(b[2], 0x5E);  // id 7Eh
  EXPECT_EQ(b[3], 0x05);
  EXPECT_EQ(b[4], kEscape);
  EXPECT_EQ(b[5], 0x5E);
  EXPECT_EQ(b[6], kEscape);
  EXPECT_EQ(b[7], 0x5D);
  for (size_t i = 1; i < b.size(); ++i) EXPECT_NE(b[i], kFlag) << i;
  Feed f(s8);
  f.bytes(b);
  ASSERT_EQ(f.got.size(), 1u);
  EXPECT_TRUE(same(f.got[0], msg(0x7E, {0x7E, 0x7D, 0x00, 0x20, 0x5E})));
}

TEST(FrameCodec, RoundTripEveryIdAndLengthInEverySet) {
  std::mt19937 rng(3);
  for (uint8_t i = 0; i < kConnectionSetCount; ++i) {
    const ConnectionSet s = connection_set_at(i);
    Feed f(s);
    std::vector<SerialMessage> sent;
    for (uint32_t id = 0; id < (1u << s.id_bits); ++id) {
      SerialMessage m = {};
      m.id = static_cast<uint16_t>(id);
      m.length = static_cast<uint8_t>(id % 9u);
      for (uint8_t k = 0; k < m.length; ++k) m.data[k] = static_cast<uint8_t>(rng());
      const Bytes b = encoded(s, m);
      ASSERT_FALSE(b.empty());
      ASSERT_LE(b.size(), kMaxEncodedBytes);
      f.bytes(b);
      sent.push_back(m);
    }
    ASSERT_EQ(f.got.size(), sent.size()) << "set " << int(s.id_bits);
    for (size_t k = 0; k < sent.size(); ++k) EXPECT_TRUE(same(f.got[k], sent[k])) << k;
    EXPECT_EQ(f.dec.counters().messages, sent.size());
    EXPECT_EQ(f.dec.counters().bad_crc, 0u);
  }
}

TEST(FrameCodec, WorstCaseStuffingFitsTheBound) {
  const ConnectionSet s11 = connection_set(IdBits::k11);
  SerialMessage m = msg(0x07E, {0x7E, 0x7E, 0x7E, 0x7E, 0x7E, 0x7E, 0x7E, 0x7E});
  const Bytes b = encoded(s11, m);
  EXPECT_GE(b.size(), 1u + 1u + 2u * 9u + 2u);
  EXPECT_LE(b.size(), kMaxEncodedBytes);
  uint8_t small[10];
  EXPECT_EQ(encode(s11, m, small, sizeof small), 0) << "too small a buffer: nothing";
}

TEST(FrameCodec, EncodeRefusesWhatTheSetCannotCarry) {
  uint8_t buf[kMaxEncodedBytes];
  EXPECT_EQ(encode(connection_set(IdBits::k7), msg(0x80, {}), buf, sizeof buf), 0);
  EXPECT_EQ(encode(connection_set(IdBits::k6), msg(0x40, {}), buf, sizeof buf), 0);
  EXPECT_EQ(encode(connection_set(IdBits::k11), msg(0x800, {}), buf, sizeof buf), 0);
  SerialMessage nine = msg(1, {1, 2, 3, 4, 5, 6, 7, 8});
  nine.length = 9;
  EXPECT_EQ(encode(connection_set(IdBits::k8), nine, buf, sizeof buf), 0);
}

TEST(FrameCodec, RandomBytesBetweenMessagesAreSkipped) {
  const ConnectionSet s7 = connection_set(IdBits::k7);
  std::mt19937 rng(11);
  Feed f(s7);
  std::vector<SerialMessage> sent;
  for (int k = 0; k < 500; ++k) {
    Bytes noise(rng() % 40u);
    for (uint8_t& x : noise) x = static_cast<uint8_t>(rng());
    f.bytes(noise);
    SerialMessage m = {};
    m.id = static_cast<uint16_t>(rng() % 128u);
    m.length = static_cast<uint8_t>(rng() % 9u);
    for (uint8_t i = 0; i < m.length; ++i) m.data[i] = static_cast<uint8_t>(rng());
    sent.push_back(m);
    f.bytes(encoded(s7, m));
  }
  // Every sent message arrives (noise may end in a flag that the next
  // message's flag cuts short: that is not a loss); a noise run very rarely
  // forms a message of its own with a valid CRC: allow none here (seeded).
  size_t k = 0;
  for (const SerialMessage& g : f.got) {
    if (k < sent.size() && same(g, sent[k])) ++k;
  }
  EXPECT_EQ(k, sent.size());
  EXPECT_EQ(f.got.size(), sent.size());
  EXPECT_GT(f.dec.counters().skipped_bytes, 1000u);
}

TEST(FrameCodec, AFlippedBitIsACrcErrorAndTheNextMessageArrives) {
  const ConnectionSet s8 = connection_set(IdBits::k8);
  const SerialMessage a = msg(0x47, {1, 2, 3, 4, 5, 6, 7, 8});
  const SerialMessage b = msg(0x48, {9, 10});
  const Bytes good = encoded(s8, a);
  int crc_rejects = 0;
  for (size_t byte = 1; byte < good.size(); ++byte) {
    for (uint8_t bit = 0; bit < 8; ++bit) {
      Bytes bad = good;
      bad[byte] = static_cast<uint8_t>(bad[byte] ^ (1u << bit));
      Feed f(s8);
      f.bytes(bad);
      f.bytes(encoded(s8, b));
      // Never the damaged message; always the next one.
      ASSERT_FALSE(f.got.empty());
      for (size_t k = 0; k + 1 < f.got.size(); ++k) EXPECT_FALSE(same(f.got[k], a));
      EXPECT_TRUE(same(f.got.back(), b)) << byte << ":" << int(bit);
      EXPECT_EQ(f.got.size(), 1u) << byte << ":" << int(bit);
      if (f.dec.counters().bad_crc == 1) ++crc_rejects;
    }
  }
  // Bits of the length byte or a byte turned into a flag/escape fail
  // otherwise (bad length, truncated); most flips are CRC rejects.
  EXPECT_GT(crc_rejects, static_cast<int>((good.size() - 3) * 8 / 2));
}

TEST(FrameCodec, ReceiverJoiningMidMessageResyncsAtTheNextFlag) {
  const ConnectionSet s6 = connection_set(IdBits::k6);
  const Bytes first = encoded(s6, msg(0x12, {0xAA, 0xBB, 0xCC}));
  const Bytes second = encoded(s6, msg(0x21, {0x01}));
  for (size_t cut = 1; cut < first.size(); ++cut) {
    Feed f(s6);
    f.bytes(Bytes(first.begin() + static_cast<long>(cut), first.end()));
    f.bytes(second);
    ASSERT_EQ(f.got.size(), 1u) << cut;
    EXPECT_TRUE(same(f.got[0], msg(0x21, {0x01})));
  }
}

TEST(FrameCodec, AMessageCutShortByAFlagIsCountedAndTheNewOneTaken) {
  const ConnectionSet s7 = connection_set(IdBits::k7);
  const Bytes a = encoded(s7, msg(0x33, {1, 2, 3, 4}));
  Feed f(s7);
  f.bytes(Bytes(a.begin(), a.begin() + 4));
  f.bytes(encoded(s7, msg(0x34, {5})));
  ASSERT_EQ(f.got.size(), 1u);
  EXPECT_EQ(f.got[0].id, 0x34);
  EXPECT_EQ(f.dec.counters().truncated, 1u);
}

TEST(FrameCodec, BadLengthAndBadEscapeAreDropped) {
  const ConnectionSet s7 = connection_set(IdBits::k7);
  Feed f(s7);
  f.bytes({kFlag, 0x10, 0x09, 1, 2, 3});        // length 9
  f.bytes({kFlag, 0x10, 0x01, kEscape, 0x00});  // 7Dh 00h is no stuffed byte
  f.bytes(encoded(s7, msg(0x10, {0x7E})));
  ASSERT_EQ(f.got.size(), 1u);
  EXPECT_EQ(f.got[0].data[0], 0x7E);
  EXPECT_EQ(f.dec.counters().bad_length, 1u);
  EXPECT_EQ(f.dec.counters().truncated, 1u);
  // 11-bit set: an id high byte above 7 is refused at once.
  Feed g(connection_set(IdBits::k11));
  g.bytes({kFlag, 0x08, 0x00, 0x00});
  EXPECT_EQ(g.dec.counters().bad_id, 1u);
}

TEST(FrameCodec, ASilenceInsideAMessageDropsItWhenAGapIsSet) {
  const ConnectionSet s7 = connection_set(IdBits::k7);
  const Bytes a = encoded(s7, msg(0x05, {1, 2, 3}));
  Feed f(s7, 500);
  f.bytes(Bytes(a.begin(), a.begin() + 3));
  f.bytes(Bytes(a.begin() + 3, a.end()), 600);  // the talker stalled
  EXPECT_TRUE(f.got.empty());
  EXPECT_EQ(f.dec.counters().truncated, 1u);
  f.bytes(a);
  EXPECT_EQ(f.got.size(), 1u);
  // Without a gap limit the same stall is harmless.
  Feed g(s7);
  g.bytes(Bytes(a.begin(), a.begin() + 3));
  g.bytes(Bytes(a.begin() + 3, a.end()), 600);
  EXPECT_EQ(g.got.size(), 1u);
}

TEST(FrameCodec, MessageStampIsItsLastByte) {
  const ConnectionSet s7 = connection_set(IdBits::k7);
  Decoder d(s7);
  const Bytes a = encoded(s7, msg(0x05, {1}));
  uint32_t t = 0xFFFFFF00u;  // across the wrap
  for (uint8_t x : a) {
    t += 87;
    d.push(x, t);
  }
  EXPECT_EQ(d.message_us(), t);
  EXPECT_EQ(byte_time_us(115200), 87u);
  EXPECT_EQ(byte_time_us(9600), 1042u);
}

}  // namespace
}  // namespace serialnet
}  // namespace mb2co
