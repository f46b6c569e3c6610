// mb2co-plant's neighbours (pcapp/plant/status_view.h): the gateway's
// network view response, built by the shared codec as the gateway builds
// it, parsed into entries, and what the user sees of it: the live line's
// summary and one event per change.
#include <gtest/gtest.h>

#include "crc/crc16.h"
#include "modbus/master_codec.h"
#include "modbus/network_pdu.h"
#include "status_view.h"

namespace mb2co {
namespace pcapp {
namespace {

using modbus::NetViewEntry;

/// The entries after a round trip through a view response's bytes.
std::vector<NetViewEntry> through_the_wire(const std::vector<NetViewEntry>& entries) {
  uint8_t request[32];
  const uint16_t n = modbus::build_net_view(request, sizeof request, 1, 1);
  uint8_t data[240];
  for (size_t i = 0; i < entries.size(); ++i) modbus::put_net_view_entry(data + 4 * i, entries[i]);
  modbus::NetMessage m{};
  m.service = modbus::NetService::kNetworkView;
  m.node_id = 1;
  m.count = static_cast<uint16_t>(4 * entries.size());
  m.data = data;
  m.data_length = m.count;
  uint8_t response[256];
  response[0] = 1;
  const uint16_t pdu = modbus::build_net_response(response + 1, 253, m);
  const uint16_t adu = append_crc(response, static_cast<uint16_t>(pdu + 1));
  modbus::NetResponse r{};
  EXPECT_EQ(modbus::parse_net_response(request, n, response, adu, r), modbus::ParseStatus::kOk);
  std::vector<NetViewEntry> out;
  EXPECT_TRUE(append_view_entries(r.message, &out));
  return out;
}

TEST(NeighboursView, EntriesSurviveTheWire) {
  const std::vector<NetViewEntry> sent = {{4, 0x05, 120}, {5, 0x04, 65535}, {9, 0xFF, 0}};
  const std::vector<NetViewEntry> got = through_the_wire(sent);
  ASSERT_EQ(got.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(got[i].node_id, sent[i].node_id);
    EXPECT_EQ(got[i].nmt_state, sent[i].nmt_state);
    EXPECT_EQ(got[i].age_ms, sent[i].age_ms);
  }
}

TEST(NeighboursView, RefusesDataThatAreNotWholeEntries) {
  const uint8_t data[6] = {4, 5, 0, 1, 5, 4};
  modbus::NetMessage m{};
  m.service = modbus::NetService::kNetworkView;
  m.data = data;
  m.data_length = 6;
  std::vector<NetViewEntry> out;
  EXPECT_FALSE(append_view_entries(m, &out));
  m.service = modbus::NetService::kSdoUpload;
  m.data_length = 4;
  EXPECT_FALSE(append_view_entries(m, &out));
}

TEST(NeighboursView, SummaryShowsEveryNodeWithItsState) {
  NeighboursView v;
  EXPECT_EQ(v.summary(), "") << "nothing before the first poll";
  v.update({});
  EXPECT_EQ(v.summary(), "neighbours none heard");
  v.update(through_the_wire({{4, 0x05, 100}, {5, 0x7F, 200}, {6, 0x04, 5000}}));
  EXPECT_EQ(v.summary(), "neighbours 4 operational, 5 pre-operational, 6 stopped (silent)");
}

TEST(NeighboursView, EachChangeIsOneEvent) {
  NeighboursView v;
  EXPECT_EQ(v.update({{4, 0x00, 10}, {5, 0x05, 10}}),
            (std::vector<std::string>{"node 4 heard: boot-up", "node 5 heard: operational"}));
  EXPECT_TRUE(v.update({{4, 0x00, 900}, {5, 0x05, 900}}).empty()) << "older heartbeats are no change";
  EXPECT_EQ(v.update({{4, 0x05, 100}, {5, 0x04, 100}}),
            (std::vector<std::string>{"node 4 boot-up -> operational", "node 5 operational -> stopped"}));
  EXPECT_EQ(v.update({{4, 0x05, 3200}, {5, 0x04, 100}}),
            (std::vector<std::string>{"node 4 silent for 3.2 s"}));
  EXPECT_TRUE(v.update({{4, 0x05, 4200}, {5, 0x04, 100}}).empty()) << "silent is said once";
  EXPECT_EQ(v.update({{4, 0x05, 65535}, {5, 0x04, 100}}), std::vector<std::string>{});
  EXPECT_EQ(v.update({{4, 0x7F, 50}, {5, 0x04, 100}}),
            (std::vector<std::string>{"node 4 operational -> pre-operational",
                                      "node 4 heard again: pre-operational"}));
}

TEST(NeighboursView, StateNames) {
  EXPECT_STREQ(nmt_state_name(0x00), "boot-up");
  EXPECT_STREQ(nmt_state_name(0x04), "stopped");
  EXPECT_STREQ(nmt_state_name(0x05), "operational");
  EXPECT_STREQ(nmt_state_name(0x7F), "pre-operational");
  EXPECT_STREQ(nmt_state_name(0xFF), "unknown");
  EXPECT_STREQ(nmt_state_name(0x42), "invalid state");
}

}  // namespace
}  // namespace pcapp
}  // namespace mb2co
