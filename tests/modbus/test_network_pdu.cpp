// The FC 2Bh / MEI 0Dh codec: the documented bytes of each service, the
// request checks (exception 03), and the master's checks of a response.
#include <gtest/gtest.h>

#include <vector>

#include "crc/crc16.h"
#include "modbus/master_codec.h"
#include "modbus/network_pdu.h"

namespace mb2co {
namespace modbus {
namespace {

using Bytes = std::vector<uint8_t>;

// The PDU of the request ADU of `length` bytes in `buf` (m.data points there).
bool parse_adu(const uint8_t* buf, uint16_t length, NetMessage& m) {
  return parse_net_request(buf + 1, static_cast<uint16_t>(length - 3u), m);
}

// Builds the response ADU from a response PDU (address 1).
Bytes response_adu(const uint8_t* pdu, uint16_t pdu_length) {
  Bytes adu(pdu_length + 3u);
  adu[0] = 1;
  for (uint16_t i = 0; i < pdu_length; ++i) adu[1u + i] = pdu[i];
  append_crc(adu.data(), static_cast<uint16_t>(pdu_length + 1u));
  return adu;
}

TEST(NetworkPdu, UploadRequestBytesAsDocumented) {
  uint8_t buf[256];
  const uint16_t n = build_net_upload(buf, sizeof buf, 1, 3, 0x1018, 1, 0, 0);
  ASSERT_EQ(n, 15u);  // address + 12-byte PDU + CRC
  const Bytes body(buf, buf + 13);
  EXPECT_EQ(body, (Bytes{0x01, 0x2B, 0x0D, 0x00, 0x00, 0x03, 0x10, 0x18, 0x01, 0x00, 0x00, 0x00, 0x00}));
  NetMessage m{};
  ASSERT_TRUE(parse_adu(buf, n, m));
  EXPECT_EQ(m.service, NetService::kSdoUpload);
  EXPECT_EQ(m.node_id, 3);
  EXPECT_EQ(m.index, 0x1018);
  EXPECT_EQ(m.sub, 1);
  EXPECT_EQ(m.count, 0u);
}

TEST(NetworkPdu, DownloadRequestCarriesSizeThenCanopenOrderData) {
  uint8_t buf[256];
  const uint8_t value[2] = {0xE8, 0x03};  // 1000 ms, little-endian as in the SDO
  const uint16_t n = build_net_download(buf, sizeof buf, 1, 2, 0x1017, 0, 2, 0, value, 2, false);
  ASSERT_EQ(n, 1u + 16u + 2u + 2u);
  EXPECT_EQ(Bytes(buf + 1, buf + 19), (Bytes{0x2B, 0x0D, 0x20, 0x00, 0x02, 0x10, 0x17, 0x00, 0x00, 0x00, 0x00,
                                             0x02, 0x00, 0x00, 0x00, 0x02, 0xE8, 0x03}));
  NetMessage m{};
  ASSERT_TRUE(parse_adu(buf, n, m));
  EXPECT_EQ(m.service, NetService::kSdoDownload);
  EXPECT_EQ(m.object_size, 2u);
  ASSERT_EQ(m.data_length, 2u);
  EXPECT_EQ(m.data[0], 0xE8);
  EXPECT_EQ(m.data[1], 0x03);
}

TEST(NetworkPdu, NmtStartAllAndView) {
  uint8_t buf[256];
  uint16_t n = build_net_nmt(buf, sizeof buf, 1, 0, 0x01);
  EXPECT_EQ(Bytes(buf + 1, buf + 14),
            (Bytes{0x2B, 0x0D, 0x60, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x01}));
  NetMessage m{};
  ASSERT_TRUE(parse_adu(buf, n, m));
  EXPECT_EQ(m.service, NetService::kNmt);
  EXPECT_EQ(net_nmt_command(m), 0x01);
  n = build_net_view(buf, sizeof buf, 1, 5);
  ASSERT_TRUE(parse_adu(buf, n, m));
  EXPECT_EQ(m.service, NetService::kNetworkView);
  EXPECT_EQ(m.node_id, 5);
  EXPECT_EQ(buf[3], 0x80);
}

// Each malformed request, one defect at a time, starting from a good one.
TEST(NetworkPdu, MalformedRequestsAreRefused) {
  uint8_t good[256];
  const uint8_t value[7] = {1, 2, 3, 4, 5, 6, 7};
  const uint16_t n = build_net_download(good, sizeof good, 1, 2, 0x2000, 1, 20, 7, value, 7, true);
  NetMessage m{};
  ASSERT_TRUE(parse_net_request(good + 1, static_cast<uint16_t>(n - 3u), m));
  const uint16_t pdu = static_cast<uint16_t>(n - 3u);
  struct Defect {
    uint16_t offset;
    uint8_t value;
    const char* what;
  };
  const Defect defects[] = {
      {2, 0x22, "reserved control bit"},
      {2, 0xE0, "service 7"},
      {2, 0xA0, "service 5"},
      {3, 0x01, "reserved byte"},
      {4, 0x00, "node 0 for an SDO"},
      {4, 0x80, "node 128"},
      {11, 0x04, "count != data bytes"},
      {15, 0x06, "part beyond object"},
      {2, 0x20, "last part short of the object"},
  };
  for (const Defect& d : defects) {
    uint8_t bad[256];
    for (uint16_t i = 0; i < pdu; ++i) bad[i] = good[1u + i];
    bad[d.offset] = d.value;
    EXPECT_FALSE(parse_net_request(bad, pdu, m)) << d.what;
  }
  EXPECT_FALSE(parse_net_request(good + 1, 11, m)) << "shorter than the header";
  const uint16_t no_whole_segments[] = {1, 6, 8, 13};
  for (const uint16_t count : no_whole_segments) {
    uint8_t part[256];
    const uint16_t k = build_net_download(part, sizeof part, 1, 2, 0x2000, 1, 20, 0, value, count, true);
    EXPECT_FALSE(parse_net_request(part + 1, static_cast<uint16_t>(k - 3u), m))
        << count << " bytes before the last part: no whole segments";
    const uint16_t last =
        build_net_download(part, sizeof part, 1, 2, 0x2000, 1, count, 0, value, count, false);
    EXPECT_TRUE(parse_net_request(part + 1, static_cast<uint16_t>(last - 3u), m))
        << "a last part of " << count;
  }
  uint8_t up[32];
  build_net_upload(up, sizeof up, 1, 2, 0x1000, 0, 0, 4);
  up[3] = 0x01;  // more follows on an upload request
  EXPECT_FALSE(parse_net_request(up + 1, 12, m));
  uint8_t nmt[32];
  build_net_nmt(nmt, sizeof nmt, 1, 2, 0x03);
  EXPECT_FALSE(parse_net_request(nmt + 1, 13, m)) << "03h is no NMT command";
  build_net_nmt(nmt, sizeof nmt, 1, 2, 0x82);
  EXPECT_TRUE(parse_net_request(nmt + 1, 13, m));
  nmt[7] = 1;  // an index on an NMT request
  EXPECT_FALSE(parse_net_request(nmt + 1, 13, m));
  uint8_t view[32];
  build_net_view(view, sizeof view, 1, 0);
  EXPECT_TRUE(parse_net_request(view + 1, 12, m));
  EXPECT_FALSE(parse_net_request(view + 1, 13, m)) << "a data byte on a view request";
}

TEST(NetworkPdu, UploadResponseRoundTripsWithTotalSizeAndMoreFollows) {
  uint8_t req[32];
  const uint16_t req_n = build_net_upload(req, sizeof req, 1, 4, 0x1008, 0, 10, 5);
  NetMessage q{};
  ASSERT_TRUE(parse_net_request(req + 1, static_cast<uint16_t>(req_n - 3u), q));
  const uint8_t window[5] = {'a', 'b', 'c', 'd', 'e'};
  NetMessage r = q;
  r.more_follows = true;
  r.object_size = 40;
  r.data = window;
  r.data_length = 5;
  uint8_t pdu[253];
  const uint16_t len = build_net_response(pdu, sizeof pdu, r);
  ASSERT_EQ(len, 16u + 5u);
  EXPECT_EQ(net_response_data_offset(NetService::kSdoUpload), 16u);
  EXPECT_EQ(pdu[2], 0x01) << "more follows";
  const Bytes rsp = response_adu(pdu, len);
  NetResponse out{};
  ASSERT_EQ(parse_net_response(req, req_n, rsp.data(), static_cast<uint16_t>(rsp.size()), out),
            ParseStatus::kOk);
  EXPECT_TRUE(out.message.more_follows);
  EXPECT_EQ(out.message.object_size, 40u);
  EXPECT_EQ(out.message.start, 10u);
  ASSERT_EQ(out.message.data_length, 5u);
  EXPECT_EQ(out.message.data[4], 'e');
  EXPECT_EQ(build_net_response(pdu, 20, r), 0u) << "does not fit";
}

TEST(NetworkPdu, ResponsesThatDoNotAnswerTheRequestAreRejected) {
  uint8_t req[32];
  const uint16_t req_n = build_net_upload(req, sizeof req, 1, 4, 0x1008, 0, 0, 0);
  NetMessage r{};
  r.node_id = 5;  // another node
  r.index = 0x1008;
  r.object_size = 1;
  const uint8_t one = 'x';
  r.data = &one;
  r.data_length = 1;
  r.count = 1;
  uint8_t pdu[64];
  uint16_t len = build_net_response(pdu, sizeof pdu, r);
  Bytes rsp = response_adu(pdu, len);
  NetResponse out{};
  EXPECT_EQ(parse_net_response(req, req_n, rsp.data(), static_cast<uint16_t>(rsp.size()), out),
            ParseStatus::kMismatch);
  r.node_id = 4;
  r.count = 2;  // count disagrees with the data
  len = build_net_response(pdu, sizeof pdu, r);
  rsp = response_adu(pdu, len);
  EXPECT_EQ(parse_net_response(req, req_n, rsp.data(), static_cast<uint16_t>(rsp.size()), out),
            ParseStatus::kBadLength);
  r.count = 1;
  len = build_net_response(pdu, sizeof pdu, r);
  rsp = response_adu(pdu, len);
  rsp[4] ^= 1;  // CRC now wrong
  EXPECT_EQ(parse_net_response(req, req_n, rsp.data(), static_cast<uint16_t>(rsp.size()), out),
            ParseStatus::kBadCrc);
}

TEST(NetworkPdu, AbortExceptionCarriesTheCodeBigEndian) {
  uint8_t req[32];
  const uint16_t req_n = build_net_upload(req, sizeof req, 1, 9, 0x1000, 0, 0, 0);
  uint8_t pdu[8];
  ASSERT_EQ(build_net_abort(pdu, 0x05040000u), 7u);
  EXPECT_EQ(Bytes(pdu, pdu + 7), (Bytes{0xAB, 0x04, 0x0D, 0x05, 0x04, 0x00, 0x00}));
  Bytes rsp = response_adu(pdu, 7);
  NetResponse out{};
  ASSERT_EQ(parse_net_response(req, req_n, rsp.data(), static_cast<uint16_t>(rsp.size()), out),
            ParseStatus::kException);
  EXPECT_EQ(out.exception, Exception::kServerDeviceFailure);
  EXPECT_EQ(out.abort_code, 0x05040000u);
  const uint8_t busy[2] = {0xAB, 0x06};
  rsp = response_adu(busy, 2);
  ASSERT_EQ(parse_net_response(req, req_n, rsp.data(), static_cast<uint16_t>(rsp.size()), out),
            ParseStatus::kException);
  EXPECT_EQ(out.exception, Exception::kServerDeviceBusy);
  EXPECT_EQ(out.abort_code, 0u);
}

TEST(NetworkPdu, ViewEntriesAndNmtEcho) {
  uint8_t req[32];
  uint16_t req_n = build_net_view(req, sizeof req, 1, 0);
  uint8_t entries[8];
  put_net_view_entry(entries, NetViewEntry{1, 0x05, 12});
  put_net_view_entry(entries + 4, NetViewEntry{3, 0x7F, net::kAgeSaturated});
  NetMessage r{};
  r.service = NetService::kNetworkView;
  r.count = 8;
  r.data = entries;
  r.data_length = 8;
  uint8_t pdu[64];
  uint16_t len = build_net_response(pdu, sizeof pdu, r);
  Bytes rsp = response_adu(pdu, len);
  NetResponse out{};
  ASSERT_EQ(parse_net_response(req, req_n, rsp.data(), static_cast<uint16_t>(rsp.size()), out),
            ParseStatus::kOk);
  ASSERT_EQ(out.message.data_length, 8u);
  EXPECT_EQ(net_view_entry(out.message, 1).node_id, 3);
  EXPECT_EQ(net_view_entry(out.message, 1).nmt_state, 0x7F);
  EXPECT_EQ(net_view_entry(out.message, 1).age_ms, 0xFFFF);
  EXPECT_EQ(net_view_entry(out.message, 0).age_ms, 12);

  req_n = build_net_nmt(req, sizeof req, 1, 7, 0x02);
  NetMessage q{};
  ASSERT_TRUE(parse_net_request(req + 1, static_cast<uint16_t>(req_n - 3u), q));
  len = build_net_response(pdu, sizeof pdu, q);  // the echo
  rsp = response_adu(pdu, len);
  ASSERT_EQ(parse_net_response(req, req_n, rsp.data(), static_cast<uint16_t>(rsp.size()), out),
            ParseStatus::kOk);
  EXPECT_EQ(net_nmt_command(out.message), 0x02);
  rsp = response_adu(pdu, len);
  pdu[12] = 0x01;  // another command echoed
  rsp = response_adu(pdu, len);
  EXPECT_EQ(parse_net_response(req, req_n, rsp.data(), static_cast<uint16_t>(rsp.size()), out),
            ParseStatus::kMismatch);
}

}  // namespace
}  // namespace modbus
}  // namespace mb2co
