// serve's CiA 309-3 side without sockets or a bus: the values of every type
// both ways, the request grammar with CANopenNode's error numbers, the line
// framing under bad input, and a client's session against a scripted
// backend (answers in request order, the limits, cancellation, events).
// Black box through ascii_*.h and serve_session.h.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "ascii_lines.h"
#include "ascii_request.h"
#include "ascii_response.h"
#include "ascii_values.h"
#include "serve_listen.h"
#include "serve_session.h"

namespace mb2co {
namespace master {
namespace {

using ascii::DataType;
using ascii::GatewayError;
using ascii::Request;

std::vector<uint8_t> bytes(std::initializer_list<uint8_t> b) {
  return std::vector<uint8_t>(b);
}

std::string format(DataType t, const std::vector<uint8_t>& b) {
  return ascii::format_value(t, b.data(), b.size());
}

TEST(ServeValues, NumbersPrintAsCanopenNodePrintsThem) {
  EXPECT_EQ(format(DataType::kU16, bytes({0x64, 0x00})), "100");
  EXPECT_EQ(format(DataType::kU64, bytes({0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF})),
            "18446744073709551615");
  EXPECT_EQ(format(DataType::kI8, bytes({0xFB})), "-5");
  EXPECT_EQ(format(DataType::kI16, bytes({0x00, 0x80})), "-32768");
  EXPECT_EQ(format(DataType::kI64, bytes({0, 0, 0, 0, 0, 0, 0, 0x80})), "-9223372036854775808");
  EXPECT_EQ(format(DataType::kX32, bytes({0x91, 0x01, 0x03, 0x00})), "0x00030191");
  EXPECT_EQ(format(DataType::kX8, bytes({0x0A})), "0x0A");
  EXPECT_EQ(format(DataType::kBoolean, bytes({1})), "1");
  EXPECT_EQ(format(DataType::kR32, bytes({0x00, 0x00, 0xC0, 0x3F})), "1.5");
  EXPECT_EQ(format(DataType::kR64, bytes({0, 0, 0, 0, 0, 0, 0xF0, 0xBF})), "-1");
  // A length that is not the type's: the bytes in hex, as CANopenNode.
  EXPECT_EQ(format(DataType::kU16, bytes({1, 2, 3})), "01 02 03");
  EXPECT_EQ(format(DataType::kHex, bytes({0xDE, 0xAD})), "DE AD");
}

TEST(ServeValues, StringsAreQuotedOrBase64OnOneLine) {
  EXPECT_EQ(format(DataType::kVisibleString, bytes({'a', ' ', '"', 'b'})), "\"a \"\"b\"");
  // NUL, CR (CANopenNode) and LF (ours) would break the line: left out.
  EXPECT_EQ(format(DataType::kVisibleString, bytes({'x', 0, '\r', '\n', 'y'})), "\"xy\"");
  EXPECT_EQ(format(DataType::kDomain, bytes({'M', 'a', 'n'})), "TWFu");
  EXPECT_EQ(format(DataType::kOctetString, bytes({'M', 'a'})), "TWE=");
  EXPECT_EQ(format(DataType::kUnicodeString, bytes({'M'})), "TQ==");
  EXPECT_EQ(format(DataType::kDomain, {}), "");
}

TEST(ServeValues, Base64RoundTripsEveryLengthAndRefusesOtherCharacters) {
  std::vector<uint8_t> data;
  for (int n = 0; n < 70; ++n) {
    std::vector<uint8_t> back;
    const std::string text = ascii::encode_base64(data.data(), data.size());
    ASSERT_TRUE(ascii::decode_base64(text, &back)) << text;
    EXPECT_EQ(back, data);
    // Without its padding too.
    std::string bare = text;
    while (!bare.empty() && bare.back() == '=') bare.pop_back();
    ASSERT_TRUE(ascii::decode_base64(bare, &back)) << bare;
    EXPECT_EQ(back, data);
    data.push_back(static_cast<uint8_t>(n * 37 + 11));
  }
  std::vector<uint8_t> out;
  EXPECT_FALSE(ascii::decode_base64("TW*u", &out));
  EXPECT_FALSE(ascii::decode_base64("TWFuT", &out));  // 1 character of a quantum: no byte
  EXPECT_FALSE(ascii::decode_base64("TQ=", &out));    // padding that does not complete a quantum
}

TEST(ServeValues, NumbersParseAsStrtoulDoesWithinTheirType) {
  std::vector<uint8_t> out;
  EXPECT_TRUE(ascii::parse_fixed_value(DataType::kU16, "0x1017", &out));
  EXPECT_EQ(out, bytes({0x17, 0x10}));
  EXPECT_TRUE(ascii::parse_fixed_value(DataType::kU8, "010", &out));  // octal, as strtoul(…, 0)
  EXPECT_EQ(out, bytes({8}));
  EXPECT_TRUE(ascii::parse_fixed_value(DataType::kI16, "-32768", &out));
  EXPECT_EQ(out, bytes({0x00, 0x80}));
  EXPECT_TRUE(ascii::parse_fixed_value(DataType::kI64, "-9223372036854775808", &out));
  EXPECT_TRUE(ascii::parse_fixed_value(DataType::kU64, "18446744073709551615", &out));
  EXPECT_TRUE(ascii::parse_fixed_value(DataType::kR32, "1.5", &out));
  EXPECT_EQ(out, bytes({0x00, 0x00, 0xC0, 0x3F}));
  for (const auto& bad :
       std::vector<std::pair<DataType, std::string>>{{DataType::kU8, "256"},
                                                     {DataType::kU16, "-1"},
                                                     {DataType::kI8, "128"},
                                                     {DataType::kI8, "-129"},
                                                     {DataType::kU64, "18446744073709551616"},
                                                     {DataType::kBoolean, "2"},
                                                     {DataType::kU32, "12abc"},
                                                     {DataType::kU32, "0x"},
                                                     {DataType::kU8, "09"},
                                                     {DataType::kR64, "1.5x"},
                                                     {DataType::kU8, ""}})
    EXPECT_FALSE(ascii::parse_fixed_value(bad.first, bad.second, &out)) << bad.second;
}

TEST(ServeValues, EveryFixedTypeReadsBackWhatItPrints) {
  const DataType types[] = {DataType::kBoolean, DataType::kI8, DataType::kI16, DataType::kI32,
                            DataType::kI64,     DataType::kU8, DataType::kU16, DataType::kU32,
                            DataType::kU64,     DataType::kX8, DataType::kX16, DataType::kX32,
                            DataType::kX64};
  for (const DataType t : types) {
    const size_t n = ascii::type_size(t);
    std::vector<uint8_t> value(n, 0xA5);
    if (t == DataType::kBoolean) value[0] = 1;
    std::vector<uint8_t> back;
    const std::string text = format(t, value);
    ASSERT_TRUE(ascii::parse_fixed_value(t, text, &back)) << ascii::type_word(t) << " " << text;
    EXPECT_EQ(back, value) << ascii::type_word(t);
  }
}

ascii::ParseContext context(int16_t node = -1) {
  ascii::ParseContext c;
  c.default_node = node;
  c.last_seq = 41;
  return c;
}

TEST(ServeRequest, ReadAndWriteWithTheirOptionalParts) {
  Request r = ascii::parse_request("[7] 3 read 0x1017 0 u16", context());
  EXPECT_EQ(r.kind, Request::Kind::kRead);
  EXPECT_EQ(r.seq, 7u);
  EXPECT_EQ(r.node, 3);
  EXPECT_EQ(r.index, 0x1017);
  EXPECT_EQ(r.type, DataType::kU16);
  // Without TYPE: hex. The default node; net 1 named; 1017 is decimal.
  r = ascii::parse_request("[8] 1 3 r 1017 0", context());
  EXPECT_EQ(r.kind, Request::Kind::kRead);
  EXPECT_EQ(r.index, 1017);
  EXPECT_EQ(r.type, DataType::kHex);
  r = ascii::parse_request("[9] R 0x1018 0x1 X32 # a comment", context(5));
  EXPECT_EQ(r.kind, Request::Kind::kRead);
  EXPECT_EQ(r.node, 5);
  EXPECT_EQ(r.sub, 1);
  EXPECT_EQ(r.type, DataType::kX32);
  r = ascii::parse_request("[10] 3 w 0x2000 0 vs \"two words\"\r", context());
  EXPECT_EQ(r.kind, Request::Kind::kWrite);
  EXPECT_EQ(std::string(r.value.begin(), r.value.end()), "two words");
  r = ascii::parse_request("[11] 3 write 0x2000 0 vs say\"\"hi", context());
  EXPECT_EQ(std::string(r.value.begin(), r.value.end()), "say\"hi");
  r = ascii::parse_request("[12] 3 write 0x1F50 1 d TWFu", context());
  EXPECT_EQ(r.value, bytes({'M', 'a', 'n'}));
  r = ascii::parse_request("[13] 3 write 0x1F50 1 hex 01 0203 4 # comment", context());
  EXPECT_EQ(r.value, bytes({1, 2, 3, 4}));
}

TEST(ServeRequest, NmtAndSettings) {
  struct Case {
    const char* line;
    Request::Kind kind;
    uint8_t nmt_or_node;
    uint32_t number;
  } const cases[] = {
      {"[1] 3 start", Request::Kind::kNmt, 0x01, 0},
      {"[1] 0 stop", Request::Kind::kNmt, 0x02, 0},
      {"[1] all preop", Request::Kind::kNmt, 0x80, 0},
      {"[1] 3 preoperational", Request::Kind::kNmt, 0x80, 0},
      {"[1] 3 reset node", Request::Kind::kNmt, 0x81, 0},
      {"[1] 3 reset comm", Request::Kind::kNmt, 0x82, 0},
      {"[1] 3 RESET Communication", Request::Kind::kNmt, 0x82, 0},
      {"[1] set network 1", Request::Kind::kSetNetwork, 0, 1},
      {"[1] 1 set node 127", Request::Kind::kSetNode, 0, 127},
      {"[1] set sdo_timeout 65535", Request::Kind::kSetSdoTimeout, 0, 65535},
      {"[1] set sdo_block 1", Request::Kind::kSetSdoBlock, 0, 1},
      {"[1] set events 0", Request::Kind::kSetEvents, 0, 0},
      {"[1] info", Request::Kind::kInfo, 0, 0},
      {"[1] log", Request::Kind::kLog, 0, 0},
      {"[1] help", Request::Kind::kHelp, 0, 0},
      {"[1] help datatype", Request::Kind::kHelpDatatype, 0, 0},
  };
  for (const Case& c : cases) {
    const Request r = ascii::parse_request(c.line, context());
    EXPECT_EQ(r.kind, c.kind) << c.line;
    if (c.kind == Request::Kind::kNmt) {
      EXPECT_EQ(r.nmt, c.nmt_or_node) << c.line;
    }
    EXPECT_EQ(r.number, c.number) << c.line;
  }
}

TEST(ServeRequest, ErrorsAreCanopenNodesNumbers) {
  struct Case {
    const char* line;
    GatewayError error;
    uint32_t seq;
  } const cases[] = {
      {"garbage", GatewayError::kSyntax, 41},  // no [SEQ]: the last one, as CANopenNode
      {"[x] 3 start", GatewayError::kSyntax, 41},
      {"[] 3 start", GatewayError::kSyntax, 41},
      {"[5]", GatewayError::kSyntax, 5},
      {"[5] 3 read 0x1017", GatewayError::kSyntax, 5},
      {"[5] 3 read 0x10170 0 u16", GatewayError::kSyntax, 5},
      {"[5] 3 read 0x1017 256", GatewayError::kSyntax, 5},
      {"[5] 3 read 0x1017 0 u24", GatewayError::kSyntax, 5},
      {"[5] 3 read 0x1017 0 u16 extra", GatewayError::kSyntax, 5},
      {"[5] 3 write 0x1017 0 u16", GatewayError::kSyntax, 5},
      {"[5] 3 write 0x1017 0 u16 65536", GatewayError::kSyntax, 5},
      {"[5] 3 write 0x1017 0 vs \"open", GatewayError::kSyntax, 5},
      {"[5] 3 write 0x1017 0 vs \"\"", GatewayError::kSyntax, 5},  // empty: CANopenNode refuses it
      {"[5] 3 write 0x1017 0 d T*", GatewayError::kSyntax, 5},
      {"[5] 3 write 0x1017 0 hex 0g", GatewayError::kSyntax, 5},
      {"[5] 3 start now", GatewayError::kSyntax, 5},
      {"[5] 3 reset", GatewayError::kSyntax, 5},
      {"[5] 3 reset everything", GatewayError::kSyntax, 5},
      {"[5] 1 2 3 start", GatewayError::kSyntax, 5},
      {"[5] set node 0", GatewayError::kSyntax, 5},
      {"[5] set sdo_block 2", GatewayError::kSyntax, 5},
      {"[5] set sdo_timeout 0", GatewayError::kSyntax, 5},
      {"[5] read 0x1017 0 u16", GatewayError::kNoDefaultNode, 5},
      {"[5] 0 read 0x1017 0 u16", GatewayError::kUnsupportedNode, 5},
      {"[5] 128 start", GatewayError::kUnsupportedNode, 5},
      {"[5] 4294967295 start", GatewayError::kUnsupportedNode, 5},
      {"[5] 2 3 start", GatewayError::kUnsupportedNet, 5},
      {"[5] set network 2", GatewayError::kUnsupportedNet, 5},
      {"[5] lss_store", GatewayError::kRequestNotSupported, 5},
      {"[5] 3 led", GatewayError::kRequestNotSupported, 5},
      {"[5] set command_size 9", GatewayError::kRequestNotSupported, 5},
      {"[5] help lss", GatewayError::kRequestNotSupported, 5},
  };
  for (const Case& c : cases) {
    const Request r = ascii::parse_request(c.line, context());
    EXPECT_EQ(r.kind, Request::Kind::kError) << c.line;
    EXPECT_EQ(r.error, c.error) << c.line;
    EXPECT_EQ(r.seq, c.seq) << c.line;
  }
  ascii::ParseContext small = context(3);
  small.max_value_bytes = 2;
  EXPECT_EQ(ascii::parse_request("[6] w 0x2000 0 hex 01 02 03", small).error, GatewayError::kOutOfMemory);
}

TEST(ServeRequest, BlanksAreAnythingButPrintableAscii) {
  EXPECT_EQ(ascii::parse_request("", context()).kind, Request::Kind::kEmpty);
  EXPECT_EQ(ascii::parse_request("  # only a comment\r", context()).kind, Request::Kind::kEmpty);
  const std::string binary(
      "\t[3]\x00\xff"
      "3\x01start\x7f",
      14);
  const Request r = ascii::parse_request(binary, context());
  EXPECT_EQ(r.kind, Request::Kind::kNmt);
  EXPECT_EQ(r.seq, 3u);
}

TEST(ServeResponse, LinesAsCanopenNodeWritesThem) {
  EXPECT_EQ(ascii::ok_line(4294967295u), "[4294967295] OK\r\n");
  EXPECT_EQ(ascii::value_line(2, "100"), "[2] 100\r\n");
  EXPECT_EQ(ascii::error_line(3, GatewayError::kSyntax), "[3] ERROR:101 #Syntax error.\r\n");
  EXPECT_EQ(ascii::abort_line(4, 0x06020000u),
            "[4] ERROR:0x06020000 #object does not exist in the object dictionary\r\n");
  const std::string help = ascii::help_text();
  EXPECT_EQ(help.substr(help.size() - 2), "\r\n");
  EXPECT_EQ(help.find("\r\n"), help.size() - 2) << "one CR LF: the end of the answer";
}

TEST(ServeLines, OverlongLinesKeepTheirStartAndDropTheRest) {
  ascii::LineFramer f(16);
  const std::string in = "[1] short\r\n[2] " + std::string(100, 'x') + "\n[3] next\nhalf";
  f.append(reinterpret_cast<const uint8_t*>(in.data()), in.size());
  std::string text;
  EXPECT_EQ(f.next(&text), ascii::LineFramer::Item::kLine);
  EXPECT_EQ(text, "[1] short\r");
  EXPECT_EQ(f.next(&text), ascii::LineFramer::Item::kOverlong);
  EXPECT_EQ(text.substr(0, 6), "[2] xx");
  EXPECT_LE(text.size(), ascii::LineFramer::kOverlongPrefix);
  EXPECT_EQ(ascii::leading_seq(text, 0), 2u);
  EXPECT_EQ(f.next(&text), ascii::LineFramer::Item::kLine);
  EXPECT_EQ(text, "[3] next");
  EXPECT_EQ(f.next(&text), ascii::LineFramer::Item::kNothing);
  EXPECT_TRUE(f.partial());
  EXPECT_EQ(f.take_partial(&text), ascii::LineFramer::Item::kLine);
  EXPECT_EQ(text, "half");
  // An overlong line fed a byte at a time holds at most max_line bytes.
  ascii::LineFramer g(16);
  for (int i = 0; i < 1000; ++i) {
    const uint8_t b = 'y';
    g.append(&b, 1);
  }
  EXPECT_EQ(g.take_partial(&text), ascii::LineFramer::Item::kOverlong);
}

TEST(ServeListen, AddressesAndWhetherOtherMachinesReachThem) {
  ListenAddress a;
  ASSERT_TRUE(parse_listen("unix:/tmp/CO_command_socket", &a));
  EXPECT_FALSE(a.tcp);
  EXPECT_EQ(a.path, "/tmp/CO_command_socket");
  EXPECT_TRUE(loopback_only(a));
  ASSERT_TRUE(parse_listen("tcp:0", &a));  // localhost unless told; the kernel's port
  EXPECT_EQ(a.host, "127.0.0.1");
  EXPECT_EQ(a.port, 0);
  EXPECT_TRUE(loopback_only(a));
  ASSERT_TRUE(parse_listen("tcp:[::1]:60000", &a));
  EXPECT_EQ(a.host, "::1");
  EXPECT_EQ(a.port, 60000);
  EXPECT_TRUE(loopback_only(a));
  ASSERT_TRUE(parse_listen("tcp:0.0.0.0:60000", &a));
  EXPECT_FALSE(loopback_only(a));
  const std::string too_long = "unix:/" + std::string(108, 'p');  // sun_path holds 107 bytes and a NUL
  for (const std::string& bad :
       {std::string("unix:"), std::string("udp:60000"), std::string("tcp:"), std::string("tcp:70000"),
        std::string("tcp:host:"), std::string("/tmp/S"), too_long})
    EXPECT_FALSE(parse_listen(bad, &a)) << bad;
}

/// A backend that answers only when the test says so.
class ScriptedBackend : public ServeBackend {
 public:
  struct Call {
    Ticket ticket;
    bool is_nmt;
    SdoJob job;
    uint8_t command, node;
    SdoDone sdo_done;
    NmtDone nmt_done;
  };
  Ticket sdo(SdoJob job, SdoDone done) override {
    calls.push_back(Call{next, false, std::move(job), 0, 0, std::move(done), nullptr});
    return next++;
  }
  Ticket nmt(uint8_t command, uint8_t node, NmtDone done) override {
    calls.push_back(Call{next, true, SdoJob(), command, node, nullptr, std::move(done)});
    return next++;
  }
  void cancel(Ticket t) override { cancelled.insert(t); }
  bool block_transfer() const override { return block; }
  bool sdo_timeout() const override { return block; }
  std::string describe() const override { return "scripted"; }

  /// Answers call `i` (once). The callback is copied first: it may ask
  /// for more, which grows `calls`.
  void upload_done(size_t i, std::vector<uint8_t> data) {
    SdoOutcome o;
    o.ok = true;
    o.data = std::move(data);
    const SdoDone done = calls[i].sdo_done;
    done(o);
  }
  void abort(size_t i, uint32_t code) {
    SdoOutcome o;
    o.abort_code = code;
    const SdoDone done = calls[i].sdo_done;
    done(o);
  }

  std::vector<Call> calls;
  std::set<Ticket> cancelled;
  Ticket next = 100;
  bool block = true;
};

class ServeSessionTest : public ::testing::Test {
 protected:
  void send(const std::string& text) {
    session.receive(reinterpret_cast<const uint8_t*>(text.data()), text.size());
  }
  std::string take() {
    const std::string s = session.output();
    session.sent(s.size());
    return s;
  }
  ScriptedBackend backend;
  SessionLimits limits;
  Session session{backend, limits, [] { return std::string("about"); }};
};

TEST_F(ServeSessionTest, AnswersComeInTheOrderOfTheRequests) {
  send("[1] 3 read 0x1017 0 u16\n[2] 4 read 0x1017 0 u16\n[3] set node 5\n[4] w 0x1017 0 u16 300\n");
  ASSERT_EQ(backend.calls.size(), 3u) << "all three transfers start at once";
  EXPECT_EQ(backend.calls[1].job.node, 4);
  EXPECT_EQ(backend.calls[2].job.node, 5) << "the default node of the line before";
  EXPECT_EQ(backend.calls[2].job.data, bytes({0x2C, 0x01}));
  EXPECT_EQ(backend.calls[0].job.timeout_ms, limits.sdo_timeout_ms);
  EXPECT_EQ(take(), "");
  backend.upload_done(1, {0xC8, 0});
  EXPECT_EQ(take(), "") << "[2] waits for [1]";
  backend.abort(0, 0x05040000u);
  EXPECT_EQ(take(), "[1] ERROR:0x05040000 #SDO protocol timed out\r\n[2] 200\r\n[3] OK\r\n");
  backend.upload_done(2, {});
  EXPECT_EQ(take(), "[4] OK\r\n");
  EXPECT_EQ(session.outstanding(), 0u);
}

TEST_F(ServeSessionTest, SettingsApplyToTheRequestsAfterThem) {
  send("[1] set sdo_timeout 250\n[2] set sdo_block 1\n[3] 3 r 0x1F50 1 d\n[4] 3 w 0x1F50 1 hex 01 02\n");
  send("[5] 3 w 0x1F50 1 hex 000102030405060708090A0B0C0D0E0F1011121314151617\n");
  ASSERT_EQ(backend.calls.size(), 3u);
  EXPECT_EQ(backend.calls[0].job.timeout_ms, 250u);
  EXPECT_TRUE(backend.calls[0].job.block);
  EXPECT_FALSE(backend.calls[1].job.block) << "2 bytes: CANopenNode goes block only above 21";
  EXPECT_TRUE(backend.calls[2].job.block);
  backend.upload_done(0, {'M', 'a', 'n'});
  backend.upload_done(1, {});
  backend.upload_done(2, {});
  EXPECT_EQ(take(), "[1] OK\r\n[2] OK\r\n[3] TWFu\r\n[4] OK\r\n[5] OK\r\n");
  backend.block = false;  // a gateway: neither can be honoured
  send("[6] set sdo_block 1\n[7] set sdo_timeout 100\n[8] set sdo_block 0\n");
  EXPECT_EQ(take(),
            "[6] ERROR:100 #Request not supported.\r\n[7] ERROR:100 #Request not supported.\r\n[8] OK\r\n");
}

TEST_F(ServeSessionTest, NmtGatewayFailuresAndInfo) {
  send("[1] 0 start\n[2] 3 reset node\n[3] info\n");
  ASSERT_EQ(backend.calls.size(), 2u);
  EXPECT_TRUE(backend.calls[0].is_nmt);
  EXPECT_EQ(backend.calls[0].node, 0);
  EXPECT_EQ(backend.calls[1].command, 0x81);
  const ServeBackend::NmtDone first = backend.calls[0].nmt_done, second = backend.calls[1].nmt_done;
  first("");
  second("the CAN interface refused the frame");
  EXPECT_EQ(take(),
            "[1] OK\r\n[2] ERROR:102 #Request not processed due to internal state.\r\n"
            "[3] about, sdo_timeout 1000 ms, sdo_block 0, events 0\r\n");
  send("[4] 3 r 0x1000 0 u32\n");
  SdoOutcome refused;
  refused.gateway_error = "the gateway answered exception 0Bh";
  const ServeBackend::SdoDone done = backend.calls[2].sdo_done;
  done(refused);
  EXPECT_EQ(take(), "[4] ERROR:102 #Request not processed due to internal state.\r\n");
}

TEST_F(ServeSessionTest, EventsGoToTheLogAndOutAtOnceWhenAskedFor) {
  session.event("first");
  send("[1] log\n[2] log\n");
  EXPECT_EQ(take(), "first\r\n\r\n") << "each line once; an empty log is an empty answer";
  send("[3] set events 1\n");
  session.event("second");
  session.event("third");
  EXPECT_EQ(take(), "[3] OK\r\nsecond\r\nthird\r\n");
  send("[4] log\n");
  EXPECT_EQ(take(), "second\nthird\r\n");
}

TEST_F(ServeSessionTest, BadInputGetsItsAnswerAndNothingElseChanges) {
  send("[9] 3 read 0x1017 0 u16\n");
  const std::string overlong = "[10] 3 w 0x2000 0 hex " + std::string(limits.max_line, 'A') + "\n";
  send(overlong);
  send(std::string("\x00\xff\xfe\n", 4));
  send("\n# comment\n[11] 3 stop");
  backend.upload_done(0, {7, 0});
  EXPECT_EQ(take(), "[9] 7\r\n[10] ERROR:600 #Running out of memory.\r\n\r\n\r\n\r\n")
      << "binary garbage, an empty line and a comment: empty answers";
  EXPECT_EQ(backend.calls.size(), 1u) << "the half line waits for its end";
  session.end_of_input();
  EXPECT_EQ(take(), "[11] ERROR:101 #Syntax error.\r\n") << "a line without its LF is not carried out";
  EXPECT_TRUE(session.finished());
}

TEST_F(ServeSessionTest, AFloodWaitsInTheSessionWhileTooManyAreOutstanding) {
  std::string many;
  for (int i = 1; i <= 100; ++i) many += "[" + std::to_string(i) + "] 3 r 0x1017 0 u16\n";
  send(many);
  EXPECT_EQ(backend.calls.size(), limits.max_outstanding);
  EXPECT_FALSE(session.wants_input());
  for (size_t i = 0; i < limits.max_outstanding; ++i) backend.upload_done(i, {1, 0});
  EXPECT_EQ(backend.calls.size(), 100u) << "the rest started as answers came";
  for (size_t i = limits.max_outstanding; i < 100; ++i) backend.upload_done(i, {1, 0});
  const std::string out = take();
  EXPECT_EQ(out.rfind("[100] 1\r\n"), out.size() - 9);
  EXPECT_TRUE(session.wants_input());
}

TEST(ServeSession, AClientThatGoesCancelsWhatItAskedFor) {
  ScriptedBackend backend;
  {
    Session s(backend, SessionLimits(), [] { return std::string(); });
    const std::string in = "[1] 3 r 0x1F50 1 d\n[2] 4 r 0x1F50 1 d\n[3] 5 start\n";
    s.receive(reinterpret_cast<const uint8_t*>(in.data()), in.size());
    backend.upload_done(1, {1});
  }
  EXPECT_EQ(backend.cancelled, (std::set<ServeBackend::Ticket>{100, 102}));
}

}  // namespace
}  // namespace master
}  // namespace mb2co
