// The network gateway on a bus at full load of other traffic (issue 23): its
// MCP2515 filters are open (the SDO client's responses and every heartbeat
// come on ids a station's filters drop), so every frame on the bus reaches
// the image. ctest runs this binary inside hil/uml/run-with-vcan.sh.
//
// The flood: 8-byte frames on 790h-79Fh (no node consumes them; above
// every id the gateway and node 2 use, so on a real bus they lose every
// arbitration to them), paced at what 500 kbit/s carries (each frame's
// exact length in bits, timing/can_bits.h), from a nice-19 thread as in
// node.sdo_flood. Meanwhile the test's Modbus master (mb2co-net-client)
// asks the gateway's own registers and, through it, node 2 (an mb2co-node):
// every request must be answered.
//
// The heartbeat is measured in the gateway's own time:
//   * mb2co-uno --image network: the image's micros() at each heartbeat's
//     last bit (--trace-can sim_us), which a slow host cannot stretch; every
//     interval within 1017h + 10 %, and the wire (mb2co-uno's `bus?`) must
//     have been busy >= 90 % of the image's time: the load it saw;
//   * mb2co-node (until that image is built): kernel receive stamps, with
//     node.sdo_flood's allowance for the one-CPU sandbox's 10 ms scheduler
//     slices (at most 2 intervals beyond the bound, none beyond 125 ms).
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "network_gateway.h"
#include "node_harness.h"
#include "platform/socketcan_port.h"
#include "timing/can_bits.h"
#include "uno_harness.h"

namespace mb2co {
namespace test {
namespace {

constexpr auto kDeadline = 60s;         // bounds a failure only
constexpr uint32_t kBitRate = 500000;   // the gateway's default (2000h/2)
constexpr size_t kIntervals = 100;      // heartbeat intervals measured (10 s)
constexpr uint16_t kHeartbeatMs = 100;  // 1017h, written through the gateway
constexpr double kMinBusyShare = 0.9;   // the wire's busy time / the image's time
constexpr size_t kMaxOverBoundOnNode = 2;
constexpr uint64_t kWorstIntervalOnNodeUs = 125000;

void nice_this_thread(int value) {
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), value);
}

uint64_t monotonic_now_us() {
  return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch())
                                   .count());
}

/// Sends 790h-79Fh frames at what kBitRate carries until `stop`, at `nice`;
/// counts them.
void flood(const std::atomic<bool>& stop, int nice, uint64_t* sent, uint64_t* bits) {
  nice_this_thread(nice);
  linux_port::SocketCanPort can;
  if (!can.open("vcan0")) return;
  const uint64_t start_us = monotonic_now_us();
  uint64_t n = 0, on_wire_bits = 0;
  while (!stop) {
    // Frames due by now: the bus has carried on_wire_bits by start + bits / rate.
    const uint64_t due_bits = (monotonic_now_us() - start_us) * kBitRate / 1000000u;
    while (on_wire_bits < due_bits) {
      CanFrame f{};
      f.id = static_cast<uint16_t>(0x790 + (n & 15u));
      f.dlc = 8;
      for (int i = 0; i < 8; ++i) f.data[i] = static_cast<uint8_t>(n >> (8 * (i & 3)));
      if (!can.send(f)) break;  // the socket's queue is full: on at the next tick
      on_wire_bits += timing::frame_bits_exact(f).total_bits;
      ++n;
    }
    std::this_thread::sleep_for(1ms);
  }
  *sent = n;
  *bits = on_wire_bits;
}

uint64_t field_u64(const std::string& line, const char* name) {
  const std::string v = field_of(line, name);
  return v.empty() ? 0 : std::stoull(v);
}

TEST(UnoNetworkLoad, HeartbeatKeepsItsPeriodAndEveryRequestIsAnsweredAtFullBusLoad) {
  TempDir dir;
  std::string error;
  const bool uno = network_gateway_is_uno();
  std::printf("gateway under test: %s\n", network_gateway_name());
  const std::unique_ptr<NodeProcess> gateway =
      start_network_gateway(dir.path("gw.pty"), kDeadline, &error,
                            uno ? std::vector<std::string>{"--trace-can"} : std::vector<std::string>{});
  ASSERT_NE(gateway, nullptr) << error;
  NodeProcess remote;
  ASSERT_TRUE(remote.start(
      {"--can", "vcan0", "--node-id", "2", "--stations", "2", "--pty", dir.path("remote.pty")}, kDeadline))
      << remote.error();
  LineChild client;
  ASSERT_TRUE(client.start({MB2CO_NET_CLIENT, gateway->device()})) << client.error();
  auto ask = [&](const std::string& command) {
    std::string line;
    if (!client.send_line(command) ||
        !client.wait_line([](const std::string&) { return true; }, kDeadline, &line))
      return std::string("no answer");
    return line;
  };
  ASSERT_EQ(ask("write 1 1017 0 6400").rfind("write size=2 ", 0), 0u) << "1017h = 100 ms";
  ASSERT_EQ(field_of(ask("upload 1 1017 0"), "data"), "6400");
  const uint64_t bound_us = kHeartbeatMs * 1100u;  // +10 %

  // The gateway's heartbeats over SocketCAN (mb2co-node) with kernel stamps.
  linux_port::SocketCanPort heartbeats;
  ASSERT_TRUE(heartbeats.open("vcan0"));
  const CanIdRange heartbeat{0x701, kCanRangeExact};
  ASSERT_TRUE(heartbeats.set_ranges(&heartbeat, 1));
  const std::string bus_before = uno ? static_cast<UnoProcess&>(*gateway).ask("bus?", "bus ") : "";

  std::atomic<bool> stop{false};
  uint64_t flood_sent = 0, flood_bits = 0;
  // mb2co-node's heartbeat is its CPU's: the flood must not take that CPU
  // (on a real bus it comes from other devices), nice 19 as in
  // node.sdo_flood. The image's is in simulated time, which the host's CPU
  // sharing cannot stretch, and mb2co-uno takes most of the sandbox's one
  // CPU: at nice 19 the flood came to 400 kbit/s, at 0 it keeps up.
  std::thread flooder(flood, std::cref(stop), uno ? 0 : 19, &flood_sent, &flood_bits);
  const uint64_t flood_from_us = monotonic_now_us();
  // The Modbus master: own registers and node 2 through the gateway, in turn.
  uint64_t requests = 0;
  std::vector<std::string> failed;
  std::thread master([&] {
    while (!stop) {
      const bool own = requests % 2 == 0;
      const std::string answer = ask(own ? "inputs 0 4" : "upload 2 1018 1");
      ++requests;
      if (answer.rfind(own ? "inputs " : "upload size=4 ", 0) != 0) failed.push_back(answer);
    }
  });

  // The heartbeat times (µs) in the gateway's own clock.
  std::vector<uint64_t> beats;
  const auto deadline = std::chrono::steady_clock::now() + 4 * kDeadline;
  while (beats.size() <= kIntervals && std::chrono::steady_clock::now() < deadline) {
    if (uno) {
      std::string line;
      if (gateway->child.wait_line([](const std::string& l) { return l.rfind("can 701#", 0) == 0; },
                                   kDeadline, &line))
        beats.push_back(field_u64(line, "sim_us"));
    } else {
      pollfd p{heartbeats.fd(), POLLIN, 0};
      poll(&p, 1, 100);
      linux_port::TimedCanFrame t;
      while (heartbeats.receive(t))
        if (t.frame.id == heartbeat.id && t.rx_time_us >= flood_from_us) beats.push_back(t.rx_time_us);
    }
  }
  stop = true;
  flooder.join();
  master.join();
  const double seconds = static_cast<double>(monotonic_now_us() - flood_from_us) / 1e6;
  ASSERT_GT(beats.size(), kIntervals) << "heartbeats in the window";

  std::printf("flood: %.1f s, %.0f frames/s (%.0f kbit/s of frames); %llu Modbus requests, %zu failed\n",
              seconds, static_cast<double>(flood_sent) / seconds,
              static_cast<double>(flood_bits) / seconds / 1000.0, static_cast<unsigned long long>(requests),
              failed.size());
  EXPECT_GE(static_cast<double>(flood_bits) / seconds, kMinBusyShare * kBitRate)
      << "the flood was not full load";
  EXPECT_TRUE(failed.empty()) << failed.size() << " unanswered, first: " << (failed.empty() ? "" : failed[0]);
  EXPECT_GE(requests, 20u) << "the master was kept waiting";

  if (uno) {
    const std::string bus_after = static_cast<UnoProcess&>(*gateway).ask("bus?", "bus ");
    const double sim_us = static_cast<double>(
        static_cast<uint32_t>(field_u64(bus_after, "sim_us") - field_u64(bus_before, "sim_us")));
    const double busy =
        static_cast<double>(field_u64(bus_after, "busy_us") - field_u64(bus_before, "busy_us"));
    const uint64_t in = field_u64(bus_after, "in") - field_u64(bus_before, "in");
    const uint64_t dropped = field_u64(bus_after, "dropped") - field_u64(bus_before, "dropped");
    std::printf("the image's wire: busy %.1f %% of %.1f s, %llu frames in, %llu dropped by the chip\n",
                100.0 * busy / sim_us, sim_us / 1e6, static_cast<unsigned long long>(in),
                static_cast<unsigned long long>(dropped));
    RecordProperty("wire_busy_percent", std::to_string(100.0 * busy / sim_us));
    RecordProperty("frames_dropped_by_the_chip", std::to_string(dropped));
    EXPECT_GE(busy / sim_us, kMinBusyShare) << "the image did not see full load";
  }
  size_t over = 0;
  uint64_t shortest = UINT64_MAX, longest = 0;
  for (size_t i = 1; i < beats.size(); ++i) {
    // The image's micros() is 32 bits: intervals are taken modulo 2^32.
    const uint64_t gap = uno ? static_cast<uint32_t>(beats[i] - beats[i - 1]) : beats[i] - beats[i - 1];
    shortest = std::min(shortest, gap);
    longest = std::max(longest, gap);
    if (gap > bound_us) {
      ++over;
      std::printf("heartbeat %zu: %llu us after the previous one\n", i, static_cast<unsigned long long>(gap));
    }
  }
  std::printf("heartbeat intervals: %zu, %.1f..%.1f ms (bound %.1f ms)\n", beats.size() - 1,
              static_cast<double>(shortest) / 1000.0, static_cast<double>(longest) / 1000.0,
              static_cast<double>(bound_us) / 1000.0);
  RecordProperty("heartbeat_longest_us", std::to_string(longest));
  if (uno) {
    EXPECT_EQ(over, 0u) << "in the image's own time no interval may pass 1017h + 10 %";
  } else {
    EXPECT_LE(over, kMaxOverBoundOnNode) << over << " intervals beyond " << bound_us << " us";
    EXPECT_LE(longest, kWorstIntervalOnNodeUs);
  }
  EXPECT_EQ(ask("write 1 1017 0 6400").rfind("write ", 0), 0u) << "still serving after the flood";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
