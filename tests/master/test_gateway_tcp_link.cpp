// GatewayTcpLink (--via-modbus tcp:HOST:PORT) against a scripted gateway: a
// listening socket of the test whose thread reads one MBAP request and
// writes the replies it is given, byte for byte. The request must be the
// MBAP frame of the codec's ADU (our transaction id, unit 255); an answer
// with another transaction id is a late one and skipped; the abort, busy,
// silence, a length field outside 2..254 and a closed connection are told
// apart. Then the command line's tcp: form.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <thread>
#include <vector>

#include "cli_options.h"
#include "gateway_answers.h"
#include "gateway_tcp_link.h"
#include "modbus/network_pdu.h"

namespace mb2co {
namespace master {
namespace {

using Bytes = std::vector<uint8_t>;

/// A Modbus/TCP gateway played by the test on 127.0.0.1, a free port.
class TcpGateway {
 public:
  TcpGateway() {
    listen_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    if (bind(listen_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(listen_, 1) != 0 ||
        getsockname(listen_, reinterpret_cast<sockaddr*>(&a), &len) != 0)
      return;
    address.port = ntohs(a.sin_port);
  }
  ~TcpGateway() {
    if (peer_.joinable()) peer_.join();
    if (conn_ >= 0) close(conn_);
    close(listen_);
  }
  TcpAddress address;

  /// In the background: accepts, reads one whole frame, writes each of
  /// `replies`; closes the connection then when `hang_up`.
  void answer(std::vector<Bytes> replies, bool hang_up = false) {
    peer_ = std::thread([this, replies, hang_up] {
      if (conn_ < 0) conn_ = accept(listen_, nullptr, nullptr);
      request_.clear();
      size_t want = 7;
      while (request_.size() < want) {
        pollfd p{conn_, POLLIN, 0};
        if (poll(&p, 1, 5000) <= 0) return;  // bounds a failure only
        uint8_t b[300];
        const ssize_t n = recv(conn_, b, want - request_.size(), 0);
        if (n <= 0) return;
        request_.insert(request_.end(), b, b + n);
        if (request_.size() == 7) want = 6u + static_cast<size_t>(request_[4] << 8 | request_[5]);
      }
      for (const Bytes& r : replies)
        if (send(conn_, r.data(), r.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(r.size())) return;
      if (hang_up) {
        close(conn_);
        conn_ = -1;
      }
    });
  }
  const Bytes& request() {
    if (peer_.joinable()) peer_.join();
    return request_;
  }

 private:
  int listen_ = -1;
  int conn_ = -1;
  std::thread peer_;
  Bytes request_;
};

/// An MBAP frame: `transaction`, unit 255, `pdu`.
Bytes frame(uint16_t transaction, const Bytes& pdu) {
  Bytes f(modbus::kMbapHeaderBytes + pdu.size());
  const modbus::MbapHeader h = {transaction, 0, static_cast<uint16_t>(pdu.size() + 1), 0xFF};
  modbus::write_mbap_header(f.data(), h);
  std::copy(pdu.begin(), pdu.end(), f.begin() + modbus::kMbapHeaderBytes);
  return f;
}

class GatewayTcpLinkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_NE(gw.address.port, 0) << "no listening socket";
    ASSERT_TRUE(link.open(gw.address, modbus::kMbapUnitDirect));
    length = modbus::build_net_upload(request, sizeof request, modbus::kMbapUnitDirect, 4, 0x1018, 1, 0, 0);
  }
  Bytes upload_answer(const Bytes& data) { return upload_answer_pdu(request, length, data); }

  TcpGateway gw;
  GatewayTcpLink link;
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

TEST_F(GatewayTcpLinkTest, TheRequestIsTheCodecsPduInAnMbapFrameAndTheAnswerIsChecked) {
  gw.answer({frame(1, upload_answer({0x2C, 0x0B, 0x00, 0x00}))});
  ASSERT_EQ(exchange(2000), GatewayChannel::Outcome::kAnswered) << got.status.message();
  ASSERT_EQ(r.message.data_length, 4u);
  EXPECT_EQ(r.message.data[0], 0x2C);
  const Bytes pdu(request + 1, request + length - 2);
  EXPECT_EQ(gw.request(), frame(1, pdu)) << "transaction 1, unit 255, no CRC";
}

TEST_F(GatewayTcpLinkTest, AnAnswerWithAnotherTransactionIdIsALateOneAndSkipped) {
  // A first exchange given up (silence), then its late answer arrives just
  // before the second exchange's own.
  gw.answer({});
  EXPECT_EQ(exchange(100), GatewayChannel::Outcome::kNoAnswer);
  gw.request();
  gw.answer({frame(1, {0xAB, 0x06}), frame(2, upload_answer({1, 2, 3, 4}))});
  ASSERT_EQ(exchange(2000), GatewayChannel::Outcome::kAnswered) << got.status.message();
  EXPECT_EQ(r.exception, modbus::Exception::kNone) << "not the late busy answer";
  EXPECT_EQ(r.message.data_length, 4u);
}

TEST_F(GatewayTcpLinkTest, AbortAndBusyAreAnswers) {
  gw.answer({frame(1, {0xAB, 0x04, 0x0D, 0x06, 0x02, 0x00, 0x00})});
  ASSERT_EQ(exchange(2000), GatewayChannel::Outcome::kAnswered);
  EXPECT_EQ(r.abort_code, 0x06020000u);
  gw.request();
  gw.answer({frame(2, {0xAB, 0x06})});
  ASSERT_EQ(exchange(2000), GatewayChannel::Outcome::kAnswered);
  EXPECT_EQ(r.exception, modbus::Exception::kServerDeviceBusy);
}

TEST_F(GatewayTcpLinkTest, SilenceABadLengthAndAHangUpAreToldApart) {
  gw.answer({});
  EXPECT_EQ(exchange(150), GatewayChannel::Outcome::kNoAnswer);
  EXPECT_EQ(got.status.message(), "no answer from unit 255 on tcp:" + gw.address.text() + " within 150 ms");
  gw.request();
  gw.answer({{0x00, 0x02, 0x00, 0x00, 0xFF, 0xFF, 0xFF}});
  EXPECT_EQ(exchange(2000), GatewayChannel::Outcome::kIoError);
  EXPECT_NE(got.status.message().find("bad MBAP header"), std::string::npos) << got.status.message();
}

TEST_F(GatewayTcpLinkTest, AGatewayThatHangsUpIsAnIoError) {
  gw.answer({}, true);
  EXPECT_EQ(exchange(2000), GatewayChannel::Outcome::kIoError);
  EXPECT_NE(got.status.message().find("closed by the gateway"), std::string::npos) << got.status.message();
}

// --via-modbus tcp:HOST:PORT on the command line.
Status apply(std::vector<std::string> words, Options* o) {
  words.insert(words.begin(), "mb2co-master");
  std::vector<const char*> argv;
  for (const std::string& w : words) argv.push_back(w.c_str());
  const cli::Parsed p = cli::parse(program(), static_cast<int>(argv.size()), argv.data());
  return p.action == cli::Action::kRun ? apply_options(p.args, o) : Status::failure(p.text);
}

TEST(MasterTcpOptions, TcpHostPortIsTheGatewayOnModbusTcp) {
  Options o;
  ASSERT_TRUE(apply({"--via-modbus", "tcp:192.0.2.7:1502", "scan"}, &o));
  EXPECT_TRUE(o.gateway_on_tcp);
  EXPECT_EQ(o.gateway_tcp.host, "192.0.2.7");
  EXPECT_EQ(o.gateway_tcp.port, 1502);
  EXPECT_EQ(o.gateway_slave, 255u) << "unit id of a server addressed by its IP address";
  EXPECT_TRUE(via_modbus_refusal(o).empty());
  Options bare;
  ASSERT_TRUE(apply({"--via-modbus", "tcp:1502", "read", "2", "1000", "0"}, &bare));
  EXPECT_EQ(bare.gateway_tcp.text(), "127.0.0.1:1502") << "localhost unless told";
  Options v6;
  ASSERT_TRUE(apply({"--via-modbus", "tcp:[::1]:1502", "scan"}, &v6));
  EXPECT_EQ(v6.gateway_tcp.host, "::1");

  Options bad;
  EXPECT_FALSE(apply({"--via-modbus", "tcp:host:0", "scan"}, &bad));
  const Status baud = apply({"--via-modbus", "tcp:1502", "--baud", "9600", "scan"}, &bad);
  EXPECT_EQ(baud.message(), "--baud is the serial line's: not with --via-modbus tcp:");
  const Status watch = apply({"--via-modbus", "tcp:1502", "watch"}, &bad);
  EXPECT_NE(watch.message().find("needs raw CAN frames"), std::string::npos) << watch.message();
}

}  // namespace
}  // namespace master
}  // namespace mb2co
