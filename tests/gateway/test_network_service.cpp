// FC 2Bh / MEI 0Dh through the gateway: a Modbus master on station 0 (node
// 1) reaches station 1 (node 2) and the rest of the bus. Every service, every
// exception, busy, the dropped pending answer, a missing node's timeout in
// virtual time, segmented and window reads of 1008h, multi-part downloads.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "crc/crc16.h"
#include "line_harness.h"
#include "modbus/master_codec.h"
#include "modbus/network_pdu.h"

namespace mb2co {
namespace test {
namespace {

using modbus::Exception;
using modbus::NetResponse;
using modbus::ParseStatus;

constexpr uint8_t kAddress = 1;  // the gateways' default Modbus address

class NetworkService : public ::testing::Test {
 protected:
  Line line{2};
  uint8_t req[256];
  uint16_t req_len = 0;
  std::vector<uint8_t> rsp;
  NetResponse r{};
  ParseStatus status = ParseStatus::kBadRequest;

  NetworkService() { line.run_ms(300); }  // boot-ups and a few heartbeats

  // Sends req (built by a build_net_* into req) to station 0 and parses the answer.
  ParseStatus ask(uint16_t length, uint32_t timeout_us = 20000) {
    req_len = length;
    rsp = line.modbus(0, req, length, timeout_us);
    status = modbus::parse_net_response(req, req_len, rsp.data(), static_cast<uint16_t>(rsp.size()), r);
    return status;
  }
  // Feeds a request without waiting for its answer.
  void send_only(const uint8_t* adu, uint16_t length) {
    line.station(0).serial_out.clear();
    for (uint16_t k = 0; k < length; ++k) {
      line.now_us += Line::kCharUs;
      line.gw(0).on_serial_byte(adu[k], line.now_us);
    }
  }
  std::string upload_string(uint8_t node, uint16_t index, uint8_t sub) {
    EXPECT_EQ(ask(modbus::build_net_upload(req, sizeof req, kAddress, node, index, sub, 0, 0)),
              ParseStatus::kOk);
    return std::string(r.message.data, r.message.data + r.message.data_length);
  }
  uint32_t upload_u32(uint8_t node, uint16_t index, uint8_t sub) {
    const std::string s = upload_string(node, index, sub);
    uint32_t v = 0;
    for (size_t i = s.size(); i-- > 0;) v = (v << 8) | static_cast<uint8_t>(s[i]);  // CANopen order
    return v;
  }
  size_t frames_with_id(uint32_t id) const {
    size_t n = 0;
    for (const Line::Sent& s : line.log) n += s.frame.id == id ? 1u : 0u;
    return n;
  }
  const CanFrame* last_frame_with_id(uint32_t id) const {
    const CanFrame* f = nullptr;
    for (const Line::Sent& s : line.log) {
      if (s.frame.id == id) f = &s.frame;
    }
    return f;
  }
};

TEST_F(NetworkService, UploadsFromAnotherNode) {
  const uint32_t vendor = upload_u32(2, 0x1018, 1);
  EXPECT_EQ(vendor, line.od_get(1, 0x1018, 1));
  EXPECT_EQ(r.message.object_size, 4u);
  EXPECT_FALSE(r.message.more_follows);
  EXPECT_GT(frames_with_id(0x602), 0u) << "the SDO went over the bus";
}

TEST_F(NetworkService, DownloadsToAnotherNode) {
  const uint8_t value[2] = {0xFA, 0x00};  // 250 ms, CANopen order
  ASSERT_EQ(ask(modbus::build_net_download(req, sizeof req, kAddress, 2, 0x1017, 0, 2, 0, value, 2, false)),
            ParseStatus::kOk);
  EXPECT_EQ(r.message.count, 2u);
  EXPECT_EQ(line.od_get(1, 0x1017, 0), 250u);
  EXPECT_EQ(line.od_get(0, 0x1017, 0), 100u) << "the gateway's own value is untouched";
}

TEST_F(NetworkService, SegmentedUploadOf1008) {
  const std::string name = upload_string(2, 0x1008, 0);
  EXPECT_EQ(name, "mb2co gateway");
  EXPECT_EQ(r.message.object_size, name.size());
  const CanFrame* seg = last_frame_with_id(0x602);
  ASSERT_NE(seg, nullptr);
  EXPECT_EQ(seg->data[0] & 0xE0, 0x60) << "segments were requested";
}

TEST_F(NetworkService, WindowReadsOfALongObject) {
  std::string got;
  bool more = true;
  uint16_t start = 0;
  int requests = 0;
  while (more && requests < 10) {
    ASSERT_EQ(ask(modbus::build_net_upload(req, sizeof req, kAddress, 2, 0x1008, 0, start, 5)),
              ParseStatus::kOk);
    EXPECT_LE(r.message.data_length, 5u);
    EXPECT_EQ(r.message.start, start);
    EXPECT_EQ(r.message.object_size, 13u);
    got.append(r.message.data, r.message.data + r.message.data_length);
    more = r.message.more_follows;
    start = static_cast<uint16_t>(start + r.message.data_length);
    ++requests;
  }
  EXPECT_EQ(got, "mb2co gateway");
  EXPECT_EQ(requests, 3);
  // A window that starts beyond the object: nothing, no more.
  ASSERT_EQ(ask(modbus::build_net_upload(req, sizeof req, kAddress, 2, 0x1008, 0, 40, 5)), ParseStatus::kOk);
  EXPECT_EQ(r.message.data_length, 0u);
  EXPECT_FALSE(r.message.more_follows);
}

TEST_F(NetworkService, OwnNodeGoesToTheLocalOdWithoutTheBus) {
  const size_t sdo_before = frames_with_id(0x601) + frames_with_id(0x581);
  EXPECT_EQ(upload_string(1, 0x1008, 0), "mb2co gateway");
  const uint8_t value[2] = {0x2C, 0x01};  // 300
  ASSERT_EQ(ask(modbus::build_net_download(req, sizeof req, kAddress, 1, 0x1017, 0, 2, 0, value, 2, false)),
            ParseStatus::kOk);
  EXPECT_EQ(line.od_get(0, 0x1017, 0), 300u);
  EXPECT_EQ(frames_with_id(0x601) + frames_with_id(0x581), sdo_before) << "no SDO on the bus";
  // The local OD answers as its SDO server would.
  EXPECT_EQ(ask(modbus::build_net_upload(req, sizeof req, kAddress, 1, 0x1234, 0, 0, 0)),
            ParseStatus::kException);
  EXPECT_EQ(r.abort_code, canopen::kAbortNoObject);
  EXPECT_EQ(ask(modbus::build_net_download(req, sizeof req, kAddress, 1, 0x1008, 0, 2, 0, value, 2, false)),
            ParseStatus::kException);
  EXPECT_EQ(r.abort_code, canopen::kAbortReadOnly);
}

TEST_F(NetworkService, ServerAbortIsCarriedInTheException) {
  ASSERT_EQ(ask(modbus::build_net_upload(req, sizeof req, kAddress, 2, 0x1234, 0, 0, 0)),
            ParseStatus::kException);
  EXPECT_EQ(r.exception, Exception::kServerDeviceFailure);
  EXPECT_EQ(r.abort_code, canopen::kAbortNoObject);
  EXPECT_EQ(rsp.size(), 1u + 7u + 2u) << "address, AB 04 0D + code, CRC";
}

TEST_F(NetworkService, MissingNodeTimesOutWithinTheDocumentedBound) {
  const uint16_t length = modbus::build_net_upload(req, sizeof req, kAddress, 9, 0x1000, 0, 0, 0);
  const uint32_t sent_us = line.now_us + length * Line::kCharUs;
  ASSERT_EQ(ask(length, 1000000), ParseStatus::kException);
  EXPECT_EQ(r.abort_code, canopen::kAbortTimeout);
  const CanFrame* abort = last_frame_with_id(0x609);
  ASSERT_NE(abort, nullptr);
  EXPECT_EQ(abort->data[0], 0x80) << "the abort went to the silent server too";
  // The answer left after the SDO timeout and well before timeout + 20 ms
  // (the harness ran 2 ms past the last byte).
  const uint32_t elapsed_us = line.now_us - sent_us;
  EXPECT_GE(elapsed_us, gateway::kNetSdoTimeoutUs);
  EXPECT_LE(elapsed_us, gateway::kNetSdoTimeoutUs + 20000u);
}

TEST_F(NetworkService, NmtToOneNodeAndToAll) {
  ASSERT_EQ(ask(modbus::build_net_nmt(req, sizeof req, kAddress, 2, canopen::kNmtStop)), ParseStatus::kOk);
  line.run_ms(5);
  EXPECT_EQ(line.gw(1).node().nmt_state(), canopen::kNmtStopped);
  EXPECT_EQ(line.gw(0).node().nmt_state(), canopen::kNmtOperational) << "only node 2";
  ASSERT_EQ(ask(modbus::build_net_nmt(req, sizeof req, kAddress, 0, canopen::kNmtEnterPreOperational)),
            ParseStatus::kOk);
  line.run_ms(5);
  EXPECT_EQ(line.gw(1).node().nmt_state(), canopen::kNmtPreOperational);
  EXPECT_EQ(line.gw(0).node().nmt_state(), canopen::kNmtPreOperational) << "all includes the gateway";
  ASSERT_EQ(ask(modbus::build_net_nmt(req, sizeof req, kAddress, 0, canopen::kNmtStart)), ParseStatus::kOk);
  line.run_ms(5);
  EXPECT_EQ(line.gw(1).node().nmt_state(), canopen::kNmtOperational);
  EXPECT_EQ(line.gw(0).node().nmt_state(), canopen::kNmtOperational);
  const CanFrame* nmt = last_frame_with_id(0x000);
  ASSERT_NE(nmt, nullptr);
  EXPECT_EQ(nmt->data[0], canopen::kNmtStart);
  EXPECT_EQ(nmt->data[1], 0) << "one broadcast frame";
  // To the gateway itself: no frame, the local node obeys.
  const size_t nmt_frames = frames_with_id(0x000);
  ASSERT_EQ(ask(modbus::build_net_nmt(req, sizeof req, kAddress, 1, canopen::kNmtStop)), ParseStatus::kOk);
  EXPECT_EQ(line.gw(0).node().nmt_state(), canopen::kNmtStopped);
  EXPECT_EQ(frames_with_id(0x000), nmt_frames);
}

// Issue 22 item 7: sent to address 0, the NMT service is executed like
// any broadcast write and never answered; the SDO services and the view
// return data, so a broadcast of them is ignored (no transfer on the bus).
TEST_F(NetworkService, BroadcastNmtIsExecutedUnansweredAndSdoIsIgnored) {
  const uint16_t unanswered = line.gw(0).modbus_slave().counters().no_responses;
  send_only(req, modbus::build_net_nmt(req, sizeof req, modbus::kBroadcastAddress, 2, canopen::kNmtStop));
  line.run_ms(20);
  EXPECT_EQ(line.gw(1).node().nmt_state(), canopen::kNmtStopped) << "executed";
  EXPECT_EQ(line.gw(0).node().nmt_state(), canopen::kNmtOperational) << "only node 2";
  EXPECT_TRUE(line.station(0).serial_out.empty()) << "never answered";
  send_only(req, modbus::build_net_nmt(req, sizeof req, modbus::kBroadcastAddress, 0, canopen::kNmtStart));
  line.run_ms(20);
  EXPECT_EQ(line.gw(1).node().nmt_state(), canopen::kNmtOperational) << "all nodes";
  EXPECT_TRUE(line.station(0).serial_out.empty());

  const size_t requests = frames_with_id(0x602);
  send_only(req, modbus::build_net_upload(req, sizeof req, modbus::kBroadcastAddress, 2, 0x1018, 1, 0, 0));
  line.run_ms(20);
  const uint8_t value[2] = {0xE8, 0x03};
  send_only(req, modbus::build_net_download(req, sizeof req, modbus::kBroadcastAddress, 2, 0x1017, 0, 2, 0,
                                            value, 2, false));
  line.run_ms(20);
  send_only(req, modbus::build_net_view(req, sizeof req, modbus::kBroadcastAddress, 0));
  line.run_ms(20);
  EXPECT_EQ(frames_with_id(0x602), requests) << "no SDO transfer started";
  EXPECT_TRUE(line.station(0).serial_out.empty());
  EXPECT_EQ(line.gw(0).modbus_slave().counters().no_responses, unanswered + 5u) << "all five unanswered";
  // The master's next request to the gateway is served as usual.
  EXPECT_EQ(upload_u32(2, 0x1017, 0), 100u) << "the broadcast download wrote nothing";
}

TEST_F(NetworkService, NetworkViewListsTheGatewayAndWhatItHears) {
  ASSERT_EQ(ask(modbus::build_net_nmt(req, sizeof req, kAddress, 2, canopen::kNmtStop)), ParseStatus::kOk);
  line.run_ms(150);  // a heartbeat in the new state
  ASSERT_EQ(ask(modbus::build_net_view(req, sizeof req, kAddress, 0)), ParseStatus::kOk);
  ASSERT_EQ(r.message.data_length, 8u);
  EXPECT_FALSE(r.message.more_follows);
  const modbus::NetViewEntry own = modbus::net_view_entry(r.message, 0);
  const modbus::NetViewEntry other = modbus::net_view_entry(r.message, 1);
  EXPECT_EQ(own.node_id, 1);
  EXPECT_EQ(own.nmt_state, canopen::kNmtOperational);
  EXPECT_EQ(own.age_ms, 0);
  EXPECT_EQ(other.node_id, 2);
  EXPECT_EQ(other.nmt_state, canopen::kNmtStopped);
  EXPECT_LE(other.age_ms, line.od_get(1, 0x1017, 0) + 5u) << "heard within its heartbeat period";
  // Starting at node 2 leaves the gateway out.
  ASSERT_EQ(ask(modbus::build_net_view(req, sizeof req, kAddress, 2)), ParseStatus::kOk);
  ASSERT_EQ(r.message.data_length, 4u);
  EXPECT_EQ(modbus::net_view_entry(r.message, 0).node_id, 2);
}

TEST_F(NetworkService, MalformedRequestsGetException03AndDisabledGets01) {
  req_len = modbus::build_net_upload(req, sizeof req, kAddress, 2, 0x1018, 1, 0, 0);
  req[4] = 0x01;  // reserved byte
  append_crc(req, static_cast<uint16_t>(req_len - 2u));
  ASSERT_EQ(ask(req_len), ParseStatus::kException);
  EXPECT_EQ(r.exception, Exception::kIllegalDataValue);
  // A later part with no download open.
  const uint8_t value[1] = {1};
  ASSERT_EQ(ask(modbus::build_net_download(req, sizeof req, kAddress, 2, 0x1006, 0, 4, 3, value, 1, false)),
            ParseStatus::kException);
  EXPECT_EQ(r.exception, Exception::kIllegalDataValue);

  const uint8_t off = 0;
  ASSERT_EQ(line.gw(0).od().write(0x2000, 10, &off, 1), canopen::kSdoOk);
  ASSERT_EQ(ask(modbus::build_net_upload(req, sizeof req, kAddress, 2, 0x1018, 1, 0, 0)),
            ParseStatus::kException);
  EXPECT_EQ(r.exception, Exception::kIllegalFunction);
}

TEST_F(NetworkService, BusyWhileATransferRunsAndOwnRegistersAnswered) {
  uint8_t slow[32];
  const uint16_t slow_len = modbus::build_net_upload(slow, sizeof slow, kAddress, 9, 0x1000, 0, 0, 0);
  send_only(slow, slow_len);
  line.run_ms(10);  // the request is under way (node 9 stays silent)
  EXPECT_TRUE(line.gw(0).network().transfer_running());
  EXPECT_TRUE(line.station(0).serial_out.empty());
  // Another 2Bh/0Dh: busy.
  ASSERT_EQ(ask(modbus::build_net_upload(req, sizeof req, kAddress, 2, 0x1018, 1, 0, 0)),
            ParseStatus::kException);
  EXPECT_EQ(r.exception, Exception::kServerDeviceBusy);
  // The gateway's own registers: answered at once.
  uint8_t read[8];
  const uint16_t read_len = modbus::build_read_request(read, sizeof read, kAddress, 0x04, 0, 2);
  const uint32_t asked_us = line.now_us;
  const std::vector<uint8_t> regs = line.modbus(0, read, read_len);
  modbus::Response rr;
  ASSERT_EQ(modbus::parse_response(read, read_len, regs.data(), static_cast<uint16_t>(regs.size()), rr),
            ParseStatus::kOk);
  EXPECT_LT(line.now_us - asked_us, 50000u);
  EXPECT_TRUE(line.gw(0).network().transfer_running());
  // The slow request's answer was given up by the master: never sent, though
  // the transfer runs to its timeout.
  line.station(0).serial_out.clear();
  line.run_ms(600);
  EXPECT_FALSE(line.gw(0).network().transfer_running());
  EXPECT_TRUE(line.station(0).serial_out.empty()) << "a late answer could pass for a later request's";
  const CanFrame* abort = last_frame_with_id(0x609);
  ASSERT_NE(abort, nullptr);
  EXPECT_EQ(abort->data[0], 0x80);
  // Served again afterwards.
  EXPECT_EQ(upload_u32(2, 0x1018, 1), line.od_get(1, 0x1018, 1));
}

// A DOMAIN 1F50h/1 at node 2 (as mb2co-node's program data): long enough for
// downloads in several parts.
struct Domain {
  std::vector<uint8_t> content, staging;
  static bool owns(void*, uint16_t index, uint8_t sub) { return index == 0x1F50 && sub == 1; }
  static uint32_t size(void* ctx, uint16_t, uint8_t) {
    return static_cast<uint32_t>(static_cast<Domain*>(ctx)->content.size());
  }
  static canopen::SdoAbort read(void* ctx, uint16_t, uint8_t, uint32_t offset, uint8_t* buf, uint16_t n) {
    const Domain& d = *static_cast<Domain*>(ctx);
    std::copy(d.content.begin() + offset, d.content.begin() + offset + n, buf);
    return canopen::kSdoOk;
  }
  static canopen::SdoAbort begin(void* ctx, uint16_t, uint8_t, uint32_t, bool) {
    static_cast<Domain*>(ctx)->staging.clear();
    return canopen::kSdoOk;
  }
  static canopen::SdoAbort write(void* ctx, uint16_t, uint8_t, uint32_t offset, const uint8_t* data,
                                 uint16_t n) {
    Domain& d = *static_cast<Domain*>(ctx);
    if (offset != d.staging.size()) return canopen::kAbortGeneral;
    d.staging.insert(d.staging.end(), data, data + n);
    return canopen::kSdoOk;
  }
  static canopen::SdoAbort commit(void* ctx, uint16_t, uint8_t, uint32_t size) {
    Domain& d = *static_cast<Domain*>(ctx);
    if (size != d.staging.size()) return canopen::kAbortGeneral;
    d.content = d.staging;
    return canopen::kSdoOk;
  }
  canopen::SdoDomain table() {
    return {&owns, &Domain::size, &Domain::read, &begin, &Domain::write, &commit, this};
  }
};

// Node 2 serves a DOMAIN 1F50h/1 (3 bytes to start with).
class MultiPart : public NetworkService {
 protected:
  Domain domain;
  canopen::SdoDomain table{};
  std::vector<uint8_t> value;

  MultiPart() : value(40) {
    domain.content.assign(3, 0xEE);
    table = domain.table();
    line.gw(1).node().sdo_server().set_domain(&table);
    for (size_t i = 0; i < value.size(); ++i) value[i] = static_cast<uint8_t>(0x30 + i);
  }
  ~MultiPart() override { line.gw(1).node().sdo_server().set_domain(nullptr); }
  ParseStatus part(uint16_t at, uint16_t n) {
    const bool more = at + n < value.size();
    return ask(modbus::build_net_download(req, sizeof req, kAddress, 2, 0x1F50, 1,
                                          static_cast<uint32_t>(value.size()), at, value.data() + at, n,
                                          more));
  }
};

TEST_F(MultiPart, PartsOfWholeSegmentsHoldOneSegmentedDownloadOpen) {
  // Parts of 14, 7, 7 and the last 12 bytes.
  const uint16_t parts[] = {14, 7, 7, 12};
  uint16_t at = 0;
  for (const uint16_t n : parts) {
    const bool more = at + n < value.size();
    ASSERT_EQ(part(at, n), ParseStatus::kOk) << "part at " << at;
    EXPECT_EQ(r.message.start, at);
    EXPECT_EQ(r.message.count, n);
    EXPECT_EQ(r.message.object_size, 40u);
    EXPECT_EQ(line.gw(0).network().download_open(), more);
    if (more) {
      EXPECT_EQ(domain.content.size(), 3u) << "the object keeps its content until the last part";
    }
    at = static_cast<uint16_t>(at + n);
  }
  EXPECT_EQ(domain.content, value);
  // One segmented download with the size indicated, 6 segments.
  int initiates = 0;
  int segments = 0;
  for (const Line::Sent& s : line.log) {
    if (s.frame.id != 0x602) continue;
    if (s.frame.data[0] == 0x21 && canopen::le32(&s.frame.data[4]) == 40u) ++initiates;
    if ((s.frame.data[0] & 0xE0) == 0x00) ++segments;
  }
  EXPECT_EQ(initiates, 1);
  EXPECT_EQ(segments, 6);
  // And read back in windows through the gateway.
  std::string back;
  for (uint16_t start = 0; start < 40; start = static_cast<uint16_t>(start + 16)) {
    ASSERT_EQ(ask(modbus::build_net_upload(req, sizeof req, kAddress, 2, 0x1F50, 1, start, 16)),
              ParseStatus::kOk);
    back.append(r.message.data, r.message.data + r.message.data_length);
  }
  EXPECT_EQ(back, std::string(value.begin(), value.end()));
}

TEST_F(MultiPart, APartBeforeTheLastOfNoWholeSegmentsIsMalformed) {
  const uint16_t no_whole_segments[] = {1, 6, 8, 13};
  for (const uint16_t n : no_whole_segments) {
    ASSERT_EQ(part(0, n), ParseStatus::kException) << n << " bytes";
    EXPECT_EQ(r.exception, Exception::kIllegalDataValue) << n << " bytes";
    EXPECT_FALSE(line.gw(0).network().download_open());
  }
  for (const Line::Sent& s : line.log) EXPECT_NE(s.frame.id, 0x602) << "nothing sent to the node";
  ASSERT_EQ(part(0, 7), ParseStatus::kOk);
  EXPECT_TRUE(line.gw(0).network().download_open());
}

TEST_F(MultiPart, AnotherRequestAbortsTheOpenDownload) {
  ASSERT_EQ(part(0, 7), ParseStatus::kOk);
  ASSERT_TRUE(line.gw(0).network().download_open());
  EXPECT_EQ(upload_u32(2, 0x1018, 1), line.od_get(1, 0x1018, 1)) << "served after the abort";
  bool aborted = false;
  for (const Line::Sent& s : line.log) {
    if (s.frame.id == 0x602 && s.frame.data[0] == 0x80)
      aborted = canopen::le32(&s.frame.data[4]) == canopen::kAbortGeneral;
  }
  EXPECT_TRUE(aborted) << "SDO abort 08000000h to the server";
  EXPECT_EQ(domain.content.size(), 3u);
}

TEST_F(MultiPart, ANextPartTooLateFindsTheTimeoutAbort) {
  ASSERT_EQ(part(0, 14), ParseStatus::kOk);
  line.run_ms(600);
  EXPECT_FALSE(line.gw(0).network().download_open());
  ASSERT_EQ(part(14, 26), ParseStatus::kException);
  EXPECT_EQ(r.abort_code, canopen::kAbortTimeout);
  EXPECT_EQ(domain.content.size(), 3u);
}

TEST_F(NetworkService, AFourByteObjectIsWrittenInOnePart) {
  const uint8_t value[4] = {0x10, 0x27, 0x00, 0x00};  // 10000 us in 1006h
  ASSERT_EQ(ask(modbus::build_net_download(req, sizeof req, kAddress, 2, 0x1006, 0, 4, 0, value, 3, true)),
            ParseStatus::kException)
      << "3 bytes are no whole segment";
  ASSERT_EQ(ask(modbus::build_net_download(req, sizeof req, kAddress, 2, 0x1006, 0, 4, 0, value, 4, false)),
            ParseStatus::kOk);
  EXPECT_EQ(line.od_get(1, 0x1006, 0), 10000u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
