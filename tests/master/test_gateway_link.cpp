// GatewayLink on a pty: libmodbus opens the slave end and sends the request,
// a peer thread on the master end plays the gateway byte for byte. What
// libmodbus 3.1 cannot do (receive a 2Bh response) is ours: the tests hold
// that a response is taken whole (normal, the 10-byte abort, a
// plain exception), that a bad CRC or silence is told apart, and that the
// request on the line is the codec's ADU.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <unistd.h>

#include <thread>
#include <vector>

#include "crc/crc16.h"
#include "gateway_answers.h"
#include "gateway_link.h"
#include "modbus/network_pdu.h"

namespace mb2co {
namespace master {
namespace {

const uint8_t kSlave = 7;

/// A pty whose slave end the link opens; the test holds the master end.
class PtyPeer {
 public:
  PtyPeer() {
    char name[128] = {};
    if (openpty(&master_, &slave_, name, nullptr, nullptr) == 0) path_ = name;
  }
  ~PtyPeer() {
    if (peer_.joinable()) peer_.join();
    if (slave_ >= 0) close(slave_);
    if (master_ >= 0) close(master_);
  }
  const std::string& path() const { return path_; }

  /// In the background: reads one request of `request_length` bytes, then
  /// writes each of `replies` (separate writes).
  void answer(size_t request_length, std::vector<std::vector<uint8_t>> replies) {
    peer_ = std::thread([this, request_length, replies] {
      request_.clear();
      while (request_.size() < request_length) {
        pollfd p{master_, POLLIN, 0};
        if (poll(&p, 1, 5000) <= 0) return;  // bounds a failure only
        uint8_t b[300];
        const ssize_t n = read(master_, b, sizeof b);
        if (n <= 0) return;
        request_.insert(request_.end(), b, b + n);
      }
      for (const auto& r : replies)
        if (write(master_, r.data(), r.size()) != static_cast<ssize_t>(r.size())) return;
    });
  }
  /// The request as the peer read it (after the exchange).
  const std::vector<uint8_t>& request() {
    if (peer_.joinable()) peer_.join();
    return request_;
  }

 private:
  int master_ = -1, slave_ = -1;
  std::string path_;
  std::thread peer_;
  std::vector<uint8_t> request_;
};

/// An ADU to slave kSlave of `pdu`, CRC appended.
std::vector<uint8_t> adu(std::vector<uint8_t> pdu) {
  pdu.insert(pdu.begin(), kSlave);
  const uint16_t crc = crc16(pdu.data(), static_cast<uint16_t>(pdu.size()));
  pdu.push_back(static_cast<uint8_t>(crc & 0xFF));
  pdu.push_back(static_cast<uint8_t>(crc >> 8));
  return pdu;
}

/// The gateway's normal answer to `request` with `data` (an upload window).
std::vector<uint8_t> upload_answer(const uint8_t* request, uint16_t length,
                                   const std::vector<uint8_t>& data) {
  return adu(upload_answer_pdu(request, length, data));
}

class GatewayLinkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_FALSE(peer.path().empty()) << "openpty failed";
    ASSERT_TRUE(link.open(peer.path(), 115200, kSlave));
    length = modbus::build_net_upload(request, sizeof request, kSlave, 4, 0x1018, 1, 0, 0);
  }
  PtyPeer peer;
  GatewayLink link;
  uint8_t request[64];
  uint16_t length = 0;
  modbus::NetResponse r{};
  GatewayChannel::Exchange got;  ///< the last exchange's, for its failure line

  /// One exchange of `request` with the link; what it came to.
  GatewayChannel::Outcome exchange(uint32_t timeout_ms) {
    got = link.exchange(request, length, timeout_ms, &r);
    return got.outcome;
  }
};

TEST_F(GatewayLinkTest, NormalResponseInTwoPiecesIsTakenWhole) {
  const std::vector<uint8_t> answer = upload_answer(request, length, {0x2C, 0x0B, 0x00, 0x00});
  const std::vector<uint8_t> head(answer.begin(), answer.begin() + 6), tail(answer.begin() + 6, answer.end());
  peer.answer(length, {head, tail});
  ASSERT_EQ(exchange(2000), GatewayChannel::Outcome::kAnswered) << got.status.message();
  EXPECT_EQ(r.exception, modbus::Exception::kNone);
  ASSERT_EQ(r.message.data_length, 4u);
  EXPECT_EQ(r.message.data[0], 0x2C);
  EXPECT_EQ(r.message.data[1], 0x0B);
  // libmodbus sent the codec's ADU: the same bytes, the same CRC.
  EXPECT_EQ(peer.request(), std::vector<uint8_t>(request, request + length));
}

TEST_F(GatewayLinkTest, AbortResponseCarriesTheCode) {
  peer.answer(length, {adu({0xAB, 0x04, 0x0D, 0x06, 0x02, 0x00, 0x00})});
  ASSERT_EQ(exchange(2000), GatewayChannel::Outcome::kAnswered) << got.status.message();
  EXPECT_EQ(r.exception, modbus::Exception::kServerDeviceFailure);
  EXPECT_EQ(r.abort_code, 0x06020000u);
}

TEST_F(GatewayLinkTest, PlainExceptionIsTakenAfterTheLineStaysQuiet) {
  peer.answer(length, {adu({0xAB, 0x04})});
  ASSERT_EQ(exchange(2000), GatewayChannel::Outcome::kAnswered) << got.status.message();
  EXPECT_EQ(r.exception, modbus::Exception::kServerDeviceFailure);
  EXPECT_EQ(r.abort_code, 0u);
}

TEST_F(GatewayLinkTest, BusyIsAnAnswer) {
  peer.answer(length, {adu({0xAB, 0x06})});
  ASSERT_EQ(exchange(2000), GatewayChannel::Outcome::kAnswered);
  EXPECT_EQ(r.exception, modbus::Exception::kServerDeviceBusy);
}

TEST_F(GatewayLinkTest, CorruptAnswerIsNoAnswer) {
  std::vector<uint8_t> answer = upload_answer(request, length, {1, 2, 3, 4});
  answer.back() ^= 0x55;
  peer.answer(length, {answer});
  EXPECT_EQ(exchange(300), GatewayChannel::Outcome::kBadAnswer);
  EXPECT_NE(got.status.message().find("no valid answer from slave 7 on " + peer.path()), std::string::npos)
      << got.status.message();
}

TEST_F(GatewayLinkTest, SilenceEndsAtTheResponseTimeout) {
  peer.answer(length, {});
  EXPECT_EQ(exchange(150), GatewayChannel::Outcome::kNoAnswer);
  EXPECT_EQ(got.status.message(), "no answer from slave 7 on " + peer.path() + " within 150 ms");
}

TEST_F(GatewayLinkTest, AnswerFromAnotherSlaveIsNotTaken) {
  std::vector<uint8_t> answer = upload_answer(request, length, {1, 2, 3, 4});
  answer[0] = kSlave + 1;
  const uint16_t crc = crc16(answer.data(), static_cast<uint16_t>(answer.size() - 2));
  answer[answer.size() - 2] = static_cast<uint8_t>(crc & 0xFF);
  answer[answer.size() - 1] = static_cast<uint8_t>(crc >> 8);
  peer.answer(length, {answer});
  EXPECT_EQ(exchange(300), GatewayChannel::Outcome::kBadAnswer);
}

}  // namespace
}  // namespace master
}  // namespace mb2co
