// Modbus/TCP framing (shared/modbus/tcp_framer.h): a request collected from
// a stream in any cut, the response framed over it with the transaction and
// unit id echoed, bad length fields, foreign protocol ids, and the RTU <->
// MBAP conversions the clients use with the RTU codecs. Black box.
#include <gtest/gtest.h>

#include <vector>

#include "crc/crc16.h"
#include "modbus/master_codec.h"
#include "modbus/tcp_framer.h"

namespace mb2co {
namespace modbus {
namespace {

using Bytes = std::vector<uint8_t>;

// FC 03, 2 registers from 0x0010, transaction 0x1234, unit 0xFF.
const Bytes kRequest = {0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0xFF, 0x03, 0x00, 0x10, 0x00, 0x02};

// Pushes `bytes` in pieces of at most `piece`, each no more than wanted().
MbapReceiver::Result feed(MbapReceiver& rx, const Bytes& bytes, size_t piece, size_t* used = nullptr) {
  size_t at = 0;
  MbapReceiver::Result r = MbapReceiver::Result::kNeedMore;
  while (at < bytes.size() && r == MbapReceiver::Result::kNeedMore) {
    size_t n = std::min<size_t>({piece, rx.wanted(), bytes.size() - at});
    r = rx.push(bytes.data() + at, static_cast<uint16_t>(n));
    at += n;
  }
  if (used != nullptr) *used = at;
  return r;
}

TEST(MbapReceiver, CollectsARequestInAnyCut) {
  for (size_t piece : {1u, 2u, 5u, 7u, 64u}) {
    MbapReceiver rx;
    ASSERT_EQ(feed(rx, kRequest, piece), MbapReceiver::Result::kRequest) << piece;
    EXPECT_EQ(rx.header().transaction, 0x1234u);
    EXPECT_EQ(rx.header().unit, 0xFFu);
    ASSERT_EQ(rx.pdu_length(), 5u);
    EXPECT_EQ(Bytes(rx.pdu(), rx.pdu() + 5), Bytes(kRequest.begin() + 7, kRequest.end()));
  }
}

TEST(MbapReceiver, WantsNoByteOfTheNextFrame) {
  MbapReceiver rx;
  Bytes two = kRequest;
  two.insert(two.end(), kRequest.begin(), kRequest.end());
  size_t used = 0;
  ASSERT_EQ(feed(rx, two, 64, &used), MbapReceiver::Result::kRequest);
  EXPECT_EQ(used, kRequest.size()) << "the second request stays in the stream";
  rx.next();
  EXPECT_EQ(rx.wanted(), kMbapHeaderBytes);
}

TEST(MbapReceiver, FramesTheResponseWithTheRequestsTransactionAndUnit) {
  MbapReceiver rx;
  ASSERT_EQ(feed(rx, kRequest, 64), MbapReceiver::Result::kRequest);
  const Bytes pdu = {0x03, 0x04, 0xAB, 0xCD, 0x00, 0x01};
  std::copy(pdu.begin(), pdu.end(), rx.pdu());
  const uint16_t n = rx.frame_response(static_cast<uint16_t>(pdu.size()));
  const Bytes want = {0x12, 0x34, 0x00, 0x00, 0x00, 0x07, 0xFF, 0x03, 0x04, 0xAB, 0xCD, 0x00, 0x01};
  EXPECT_EQ(Bytes(rx.frame(), rx.frame() + n), want);
}

TEST(MbapReceiver, ALengthOutsideTwoTo254EndsTheStream) {
  for (unsigned length : {0u, 1u, 255u, 0xFFFFu}) {
    MbapReceiver rx;
    Bytes header = {0x00, 0x01, 0x00, 0x00, static_cast<uint8_t>(length >> 8), static_cast<uint8_t>(length),
                    1};
    EXPECT_EQ(feed(rx, header, 7), MbapReceiver::Result::kBadLength) << length;
  }
  for (unsigned length : {2u, 254u}) {
    MbapReceiver rx;
    Bytes header = {0x00, 0x01, 0x00, 0x00, static_cast<uint8_t>(length >> 8), static_cast<uint8_t>(length),
                    1};
    EXPECT_EQ(feed(rx, header, 7), MbapReceiver::Result::kNeedMore) << length;
    EXPECT_EQ(rx.wanted(), length - 1u);
  }
}

TEST(MbapReceiver, AFrameOfAnotherProtocolIsWholeAndForeign) {
  MbapReceiver rx;
  Bytes foreign = kRequest;
  foreign[3] = 0x01;
  size_t used = 0;
  EXPECT_EQ(feed(rx, foreign, 3, &used), MbapReceiver::Result::kForeign);
  EXPECT_EQ(used, foreign.size()) << "skipped whole: the next frame starts after it";
  rx.next();
  EXPECT_EQ(feed(rx, kRequest, 64), MbapReceiver::Result::kRequest);
}

TEST(MbapConversion, AnRtuRequestCarriedOverTcpAndItsAnswerBack) {
  uint8_t rtu[8];
  const uint16_t n = build_read_request(rtu, sizeof rtu, 0x11, fc::kReadInputRegisters, 0x0010, 2);
  uint8_t frame[kMaxMbapFrameBytes];
  const uint16_t f = mbap_from_rtu(frame, sizeof frame, rtu, n, 0xBEEF);
  const Bytes want = {0xBE, 0xEF, 0x00, 0x00, 0x00, 0x06, 0x11, 0x04, 0x00, 0x10, 0x00, 0x02};
  EXPECT_EQ(Bytes(frame, frame + f), want);

  const Bytes answer = {0xBE, 0xEF, 0x00, 0x00, 0x00, 0x07, 0x11, 0x04, 0x04, 0x00, 0x2A, 0x00, 0x2B};
  uint8_t adu[kMaxAduBytes];
  const uint16_t a = rtu_from_mbap(adu, sizeof adu, answer.data(), static_cast<uint16_t>(answer.size()));
  ASSERT_EQ(a, 1u + 6u + kCrcBytes);
  Response r;
  ASSERT_EQ(parse_response(rtu, n, adu, a, r), ParseStatus::kOk);
  EXPECT_EQ(r.reg(0), 0x2Au);
  EXPECT_EQ(r.reg(1), 0x2Bu);
}

TEST(MbapConversion, RefusesWhatIsNotOneWholeModbusFrame) {
  uint8_t adu[kMaxAduBytes];
  Bytes short_frame(kRequest.begin(), kRequest.end() - 1);
  EXPECT_EQ(rtu_from_mbap(adu, sizeof adu, short_frame.data(), static_cast<uint16_t>(short_frame.size())),
            0u);
  Bytes foreign = kRequest;
  foreign[2] = 0x80;
  EXPECT_EQ(rtu_from_mbap(adu, sizeof adu, foreign.data(), static_cast<uint16_t>(foreign.size())), 0u);
  uint8_t small[6];
  EXPECT_EQ(rtu_from_mbap(small, sizeof small, kRequest.data(), static_cast<uint16_t>(kRequest.size())), 0u);
  const uint8_t rtu[3] = {1, 3, 0};
  uint8_t frame[16];
  EXPECT_EQ(mbap_from_rtu(frame, sizeof frame, rtu, 3, 1), 0u) << "no PDU in it";
}

}  // namespace
}  // namespace modbus
}  // namespace mb2co
