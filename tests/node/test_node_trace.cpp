// mb2co-node --trace-can on vcan0 (ctest runs this binary inside
// hil/uml/run-with-vcan.sh: a private vcan0): candump -L records the bus
// beside the node, the test drives an NMT start and two SDO uploads with
// cansend, and the frames of the node's trace (what it sent and what it took
// in) are the frames candump saw, in the candump -L text or as a pcap of
// LINKTYPE_CAN_SOCKETCAN read back here by its own parser. Time stamps differ
// (each side stamps its own reception), so they are only checked to be the
// host's wall clock, in order.
#include <gtest/gtest.h>
#include <signal.h>
#include <stdint.h>
#include <time.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

#include "node_harness.h"

namespace mb2co {
namespace test {
namespace {

constexpr auto kUmlDeadline = 60s;        // bounds a failure only
const char* const kProbeId = "1FFFFFFF";  // start_candump_listening's probe: no node's frame

uint64_t realtime_us() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

/// A frame as "ID#DATA" with its time stamp (µs since the epoch).
struct Stamped {
  uint64_t t_us;
  std::string frame;
};

/// "(1732561234.123456) vcan0 705#05" → stamp and "705#05"; false otherwise.
bool parse_log_line(const std::string& line, Stamped* out) {
  static const std::regex kLine(
      R"(\((\d+)\.(\d{6})\) vcan0 ([0-9A-F]{3}|[0-9A-F]{8})#([0-9A-F]{0,16}|R\d?))");
  std::smatch m;
  if (!std::regex_match(line, m, kLine)) return false;
  out->t_us = std::stoull(m[1]) * 1000000u + std::stoull(m[2]);
  out->frame = m[3].str() + "#" + m[4].str();
  return true;
}

bool cansend(const std::string& frame) {
  LineChild c;
  return c.start({"cansend", "vcan0", frame}) && c.wait_exit(kUmlDeadline) == 0;
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

uint32_t le32(const std::string& b, size_t at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(b[at + static_cast<size_t>(i)]);
  return v;
}

/// The frames of a pcap file (libpcap format, µs, little-endian, link type
/// 227), read by the layout of pcap-savefile(5) and linux/can.h, not by
/// the writer's code; a failure is reported through gtest.
std::vector<Stamped> read_pcap(const std::string& bytes) {
  std::vector<Stamped> frames;
  EXPECT_GE(bytes.size(), 24u);
  if (bytes.size() < 24) return frames;
  EXPECT_EQ(le32(bytes, 0), 0xA1B2C3D4u) << "magic: µs stamps, little-endian";
  EXPECT_EQ(le32(bytes, 4), 0x00040002u) << "version 2.4";
  EXPECT_EQ(le32(bytes, 20), 227u) << "LINKTYPE_CAN_SOCKETCAN";
  size_t at = 24;
  while (at + 16 <= bytes.size()) {
    const uint32_t sec = le32(bytes, at), usec = le32(bytes, at + 4), stored = le32(bytes, at + 8);
    EXPECT_EQ(stored, 16u) << "a SocketCAN frame is 16 bytes";
    EXPECT_EQ(le32(bytes, at + 12), 16u);
    EXPECT_LT(usec, 1000000u);
    if (stored != 16 || at + 16 + stored > bytes.size()) break;
    const size_t f = at + 16;
    uint32_t can_id = 0;
    for (size_t i = 0; i < 4; ++i) can_id = (can_id << 8) | static_cast<uint8_t>(bytes[f + i]);  // big-endian
    const bool extended = (can_id & 0x80000000u) != 0, rtr = (can_id & 0x40000000u) != 0;
    const unsigned len = static_cast<uint8_t>(bytes[f + 4]);
    EXPECT_LE(len, 8u);
    char text[40];
    int n = std::snprintf(text, sizeof text, extended ? "%08X#" : "%03X#", can_id & 0x1FFFFFFFu);
    if (rtr) {
      std::snprintf(text + n, sizeof text - static_cast<size_t>(n), len ? "R%u" : "R", len);
    } else {
      for (unsigned i = 0; i < len && i < 8; ++i)
        n += std::snprintf(text + n, sizeof text - static_cast<size_t>(n), "%02X",
                           static_cast<unsigned>(static_cast<uint8_t>(bytes[f + 8 + i])));
    }
    frames.push_back({static_cast<uint64_t>(sec) * 1000000u + usec, text});
    at += 16 + stored;
  }
  EXPECT_EQ(at, bytes.size()) << "no partial record at the end";
  return frames;
}

std::vector<Stamped> read_text(const std::string& text) {
  std::vector<Stamped> frames;
  size_t start = 0;
  while (start < text.size()) {
    const size_t nl = text.find('\n', start);
    EXPECT_NE(nl, std::string::npos) << "the trace ends in a whole line";
    if (nl == std::string::npos) break;
    Stamped s{};
    const std::string line = text.substr(start, nl - start);
    EXPECT_TRUE(parse_log_line(line, &s)) << "not a candump -L line: " << line;
    frames.push_back(s);
    start = nl + 1;
  }
  return frames;
}

std::vector<std::string> sorted_frames(const std::vector<Stamped>& stamped) {
  std::vector<std::string> v;
  for (const Stamped& s : stamped) v.push_back(s.frame);
  std::sort(v.begin(), v.end());
  return v;
}

bool has(const std::vector<std::string>& frames, const std::string& prefix) {
  return std::any_of(frames.begin(), frames.end(),
                     [&](const std::string& f) { return f.rfind(prefix, 0) == 0; });
}

/// Runs node 5 with --trace-can PATH beside candump, drives traffic, stops
/// both; the frames candump saw (the probes left out) and the trace's.
void run_traced_node(const std::string& trace_path, std::vector<Stamped>* bus, uint64_t* started_us) {
  TempDir dir;
  LineChild candump;
  const Status listening = start_candump_listening(candump, kUmlDeadline);
  ASSERT_TRUE(listening) << listening.message();
  *started_us = realtime_us();
  // Every candump line from here on, whatever a wait was looking for.
  auto wait_candump = [&](const std::string& prefix) {
    return candump.wait_line(
        [&](const std::string& l) {
          Stamped s{};
          if (!parse_log_line(l, &s)) return false;
          if (s.frame.rfind(kProbeId, 0) != 0) bus->push_back(s);
          return s.frame.rfind(prefix, 0) == 0;
        },
        kUmlDeadline);
  };

  NodeProcess node;
  ASSERT_TRUE(node.start(
      {"--can", "vcan0", "--node-id", "5", "--pty", dir.path("node.pty"), "--trace-can", trace_path},
      kUmlDeadline))
      << node.error();
  ASSERT_TRUE(wait_candump("705#00")) << "boot-up";
  // It starts operational by itself: NMT enter pre-operational, then start.
  ASSERT_TRUE(cansend("000#8005"));
  ASSERT_TRUE(wait_candump("705#7F")) << "heartbeat: pre-operational";
  ASSERT_TRUE(cansend("000#0105"));
  ASSERT_TRUE(wait_candump("705#05")) << "heartbeat: operational";
  ASSERT_TRUE(cansend("605#4018100100000000"));  // SDO upload 1018h/1 vendor id
  ASSERT_TRUE(wait_candump("585#"));
  ASSERT_TRUE(cansend("605#4000100000000000"));  // SDO upload 1000h device type
  ASSERT_TRUE(wait_candump("585#"));
  EXPECT_EQ(node.stop(), 0);
  EXPECT_EQ(node.child.stderr_text(), "");
  // The node is gone: once candump has the probe after it, it has every
  // frame the node sent or took in.
  ASSERT_TRUE(cansend(std::string(kProbeId) + "#"));
  ASSERT_TRUE(wait_candump(kProbeId));
  ASSERT_TRUE(candump.signal(SIGINT));
  EXPECT_EQ(candump.wait_exit(kUmlDeadline), 0);
}

/// The trace: the frames candump saw, stamped by the wall clock during the
/// run and in order; both directions are in it.
void expect_trace_is_the_bus(const std::vector<Stamped>& trace, const std::vector<Stamped>& bus,
                             uint64_t started_us) {
  const std::vector<std::string> traced = sorted_frames(trace), seen = sorted_frames(bus);
  EXPECT_EQ(traced, seen);
  EXPECT_TRUE(has(traced, "705#00")) << "its boot-up (sent)";
  EXPECT_TRUE(has(traced, "000#8005")) << "an NMT command (received)";
  EXPECT_TRUE(has(traced, "705#7F")) << "a heartbeat (sent)";
  EXPECT_TRUE(has(traced, "605#40181001")) << "the SDO request (received)";
  EXPECT_TRUE(has(traced, "585#42181001")) << "the SDO response (sent)";
  const uint64_t ended_us = realtime_us();
  for (size_t i = 0; i < trace.size(); ++i) {
    EXPECT_GE(trace[i].t_us, started_us) << trace[i].frame;
    EXPECT_LE(trace[i].t_us, ended_us) << trace[i].frame;
    if (i > 0) {
      EXPECT_GE(trace[i].t_us, trace[i - 1].t_us) << "in order at " << trace[i].frame;
    }
  }
}

/// Runs the node with a trace named `file` and checks what `read` makes of it.
void check_trace(const std::string& file, std::vector<Stamped> (*read)(const std::string& bytes)) {
  TempDir dir;
  std::vector<Stamped> bus;
  uint64_t started_us = 0;
  run_traced_node(dir.path(file), &bus, &started_us);
  if (::testing::Test::HasFatalFailure()) return;
  expect_trace_is_the_bus(read(file_bytes(dir.path(file))), bus, started_us);
}

TEST(TraceCan, CandumpTextHoldsTheFramesCandumpSaw) {
  check_trace("node.log", &read_text);
}

TEST(TraceCan, PcapHoldsTheFramesCandumpSaw) {
  check_trace("node.pcap", &read_pcap);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
