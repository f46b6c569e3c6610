// The network gateway on a bus loaded with other traffic (issue 23 item 5).
// Its MCP2515 filters are open (the SDO client's responses and every
// heartbeat come on ids a station's filters drop; acceptance filters for
// those ranges were measured at +936..+1,204 B, beyond the image's budget:
// docs/gateway-network.md, "At bus load"), so every frame on the bus
// reaches the image, and at full load it keeps up with about 60 % of them.
// ctest runs this binary inside hil/uml/run-with-vcan.sh.
//
// The load: 8-byte frames on 790h-79Fh (no node consumes them; above every
// id the gateway and node 2 use, so on a real bus they lose every
// arbitration to them), paced at a bit rate (each frame's exact length in
// bits, timing/can_bits.h) from a thread as in node.sdo_flood. Meanwhile
// the test's Modbus master (mb2co-net-client) asks the gateway's own
// registers and, through it, node 2 (an mb2co-node), in turn. Two phases:
//   * full load (500 kbit/s of frames): the heartbeat holds (below), the
//     gateway's own registers are always answered, and every remote upload
//     is answered: its data, or exception 04 with 05040000h (the SDO
//     timeout) when the chip dropped node 2's response with the frames it
//     had no room for; at most kMaxLost of them so;
//   * a third of the bus (kThirdBitRate): the same; the frames come in
//     small bursts (as from many nodes on a real bus), and the chip's two
//     receive buffers overflow whenever a burst outruns the image's loop.
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

constexpr auto kDeadline = 60s;        // bounds a failure only
constexpr uint32_t kBitRate = 500000;  // the gateway's default (2000h/2)
constexpr uint32_t kFullLoad = kBitRate;
/// A third of the bus in 8-byte frames (~1,400 frames/s; 127 nodes'
/// heartbeats every 100 ms are 1,270/s): the image nearly keeps up, the
/// frames coming in small bursts (measured: 4-5 % dropped by the chip, 0-4
/// of 560-683 remote uploads 05040000h).
constexpr uint32_t kThirdBitRate = kBitRate / 3;
constexpr size_t kIntervals = 100;      // heartbeat intervals measured (10 s)
constexpr uint16_t kHeartbeatMs = 100;  // 1017h, written through the gateway
constexpr double kMinBusyShare = 0.9;   // the wire's busy time / the image's time, of the load asked
/// Of the remote uploads, the share that may end in 05040000h at any load:
/// three of four (measured at full load: 29-53 %, the chip dropping ~42 %
/// of all frames; a response is lost with the frames the chip has no room
/// for). Over kMinUploads, a true share of 0.55 passes 3/4 with p < 1e-3.
constexpr double kMaxLost = 3.0 / 4.0;
constexpr uint64_t kMinUploads = 80;
constexpr uint32_t kClientTimeoutMs = 20000;
constexpr uint64_t kFloodLeadBeats = 2;
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

/// Sends 790h-79Fh frames at `bit_rate` bits/s of frames until `stop`, at
/// `nice`; counts them. Paced by the wall clock, and by the gateway's own
/// clock too: never more than kFloodLeadBeats heartbeat periods of frames
/// beyond its heartbeats seen. A host that runs the simulated Uno slower
/// than the wall clock would otherwise pile up a backlog that only grows
/// (19 s of the image's time took 226 s at load 6, the client's 20 s
/// waits ran out); with the lead the image's wire stays busy all the same.
void flood(const std::atomic<bool>& stop, uint32_t bit_rate, int nice, uint64_t* sent, uint64_t* bits) {
  nice_this_thread(nice);
  linux_port::SocketCanPort can;
  const CanIdRange heartbeat{0x701, kCanRangeExact};
  if (!can.open("vcan0") || !can.set_ranges(&heartbeat, 1)) return;
  const uint64_t start_us = monotonic_now_us();
  uint64_t n = 0, on_wire_bits = 0, beats = 0;
  while (!stop) {
    for (linux_port::TimedCanFrame t; can.receive(t);) ++beats;
    // Frames due by now: the bus has carried on_wire_bits by start + bits / rate.
    const uint64_t wall_bits = (monotonic_now_us() - start_us) * bit_rate / 1000000u;
    const uint64_t gateway_bits = (beats + kFloodLeadBeats) * kHeartbeatMs * bit_rate / 1000u;
    const uint64_t due_bits = std::min(wall_bits, gateway_bits);
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

/// What one phase of load saw.
struct Phase {
  uint64_t own = 0;                ///< requests for the gateway's own registers (FC 04)
  uint64_t remote = 0;             ///< uploads of node 2's 1018h/1 through the gateway
  uint64_t lost = 0;               ///< of those, ended in exception 04 / 05040000h (SDO timeout)
  std::vector<std::string> wrong;  ///< any other answer: not answered as documented
  double seconds = 0, flood_bits_per_s = 0, flood_frames_per_s = 0;
  double busy_share = 0;                   ///< the image's wire (Uno only)
  uint64_t chip_in = 0, chip_dropped = 0;  ///< frames from the bus, and those the chip had no room for
  std::vector<uint64_t> beats;             ///< heartbeat times (µs) in the gateway's own clock
};

class UnoNetworkLoad : public ::testing::Test {
 protected:
  void SetUp() override {
    uno_ = network_gateway_is_uno();
    std::printf("gateway under test: %s\n", network_gateway_name());
    std::string error;
    gateway_ =
        start_network_gateway(dir_.path("gw.pty"), kDeadline, &error,
                              uno_ ? std::vector<std::string>{"--trace-can"} : std::vector<std::string>{});
    ASSERT_NE(gateway_, nullptr) << error;
    ASSERT_TRUE(remote_.start(
        {"--can", "vcan0", "--node-id", "2", "--stations", "2", "--pty", dir_.path("remote.pty")}, kDeadline))
        << remote_.error();
    // A loaded host runs the simulated Uno slower than the wall clock (10 s
    // of the image's time took 39 s at load 8 on 2 cores): the client waits
    // kClientTimeoutMs of wall time for an answer the image gives in its own.
    ASSERT_TRUE(client_.start({MB2CO_NET_CLIENT, gateway_->device(), "1", std::to_string(kClientTimeoutMs)}))
        << client_.error();
    ASSERT_EQ(ask("write 1 1017 0 6400").rfind("write size=2 ", 0), 0u) << "1017h = 100 ms";
    ASSERT_EQ(field_of(ask("upload 1 1017 0"), "data"), "6400");
    ASSERT_TRUE(heartbeats_.open("vcan0"));
    ASSERT_TRUE(heartbeats_.set_ranges(&kHeartbeat, 1));
  }

  std::string ask(const std::string& command) {
    std::string line;
    if (!client_.send_line(command) ||
        !client_.wait_line([](const std::string&) { return true; }, kDeadline, &line))
      return std::string("no answer");
    return line;
  }

  /// The load of `bit_rate` for kIntervals heartbeats and kMinUploads
  /// remote uploads at least, the Modbus master asking all along.
  Phase run(uint32_t bit_rate) {
    Phase p;
    UnoProcess* uno = uno_ ? static_cast<UnoProcess*>(gateway_.get()) : nullptr;
    const std::string bus_before = uno ? uno->ask("bus?", "bus ") : "";
    std::atomic<bool> stop{false};
    uint64_t flood_sent = 0, flood_bits = 0;
    // mb2co-node's heartbeat is its CPU's: the flood must not take that CPU
    // (on a real bus it comes from other devices), nice 19 as in
    // node.sdo_flood. The image's is in simulated time, which the host's CPU
    // sharing cannot stretch, and mb2co-uno takes most of the sandbox's one
    // CPU: at nice 19 the flood came to 400 kbit/s, at 0 it keeps up.
    std::thread flooder(flood, std::cref(stop), bit_rate, uno_ ? 0 : 19, &flood_sent, &flood_bits);
    const uint64_t from_us = monotonic_now_us();
    std::atomic<uint64_t> remote_done{0};
    std::thread master([&] {
      while (!stop) {
        const bool own = (p.own + p.remote) % 2 == 0;
        const std::string answer = ask(own ? "inputs 0 4" : "upload 2 1018 1");
        if (own) {
          ++p.own;
          if (answer.rfind("inputs ", 0) != 0) p.wrong.push_back(answer);
        } else {
          ++p.remote;
          ++remote_done;
          if (answer.rfind("exception 04 abort=05040000 ", 0) == 0) {
            ++p.lost;
          } else if (answer.rfind("upload size=4 ", 0) != 0) {
            p.wrong.push_back(answer);
          }
        }
      }
    });
    const auto deadline = std::chrono::steady_clock::now() + 4 * kDeadline;
    while ((p.beats.size() <= kIntervals || remote_done < kMinUploads) &&
           std::chrono::steady_clock::now() < deadline) {
      if (uno) {
        std::string line;
        if (uno->child.wait_line([](const std::string& l) { return l.rfind("can 701#", 0) == 0; }, kDeadline,
                                 &line))
          p.beats.push_back(field_u64(line, "sim_us"));
      } else {
        pollfd pfd{heartbeats_.fd(), POLLIN, 0};
        poll(&pfd, 1, 100);
        linux_port::TimedCanFrame t;
        while (heartbeats_.receive(t))
          if (t.frame.id == kHeartbeat.id && t.rx_time_us >= from_us) p.beats.push_back(t.rx_time_us);
      }
    }
    stop = true;
    flooder.join();
    master.join();
    p.seconds = static_cast<double>(monotonic_now_us() - from_us) / 1e6;
    p.flood_bits_per_s = static_cast<double>(flood_bits) / p.seconds;
    p.flood_frames_per_s = static_cast<double>(flood_sent) / p.seconds;
    std::printf(
        "load %u bit/s: %.1f s, %.0f frames/s (%.0f kbit/s of frames); %llu own requests, %llu remote "
        "uploads, %llu of them 05040000h, %zu answered otherwise\n",
        bit_rate, p.seconds, p.flood_frames_per_s, p.flood_bits_per_s / 1000.0,
        static_cast<unsigned long long>(p.own), static_cast<unsigned long long>(p.remote),
        static_cast<unsigned long long>(p.lost), p.wrong.size());
    if (uno) {
      const std::string bus_after = uno->ask("bus?", "bus ");
      const double sim_us = static_cast<double>(
          static_cast<uint32_t>(field_u64(bus_after, "sim_us") - field_u64(bus_before, "sim_us")));
      p.busy_share =
          static_cast<double>(field_u64(bus_after, "busy_us") - field_u64(bus_before, "busy_us")) / sim_us;
      p.chip_in = field_u64(bus_after, "in") - field_u64(bus_before, "in");
      p.chip_dropped = field_u64(bus_after, "dropped") - field_u64(bus_before, "dropped");
      std::printf("the image's wire: busy %.1f %% of %.1f s, %llu frames in, %llu dropped by the chip\n",
                  100.0 * p.busy_share, sim_us / 1e6, static_cast<unsigned long long>(p.chip_in),
                  static_cast<unsigned long long>(p.chip_dropped));
    }
    return p;
  }

  /// Every request answered as documented, the load what was asked: on
  /// the image, its wire's busy time in its own time (a host that runs it
  /// slower than the wall clock gives it more load, never less); on
  /// mb2co-node, the flood's rate.
  void expect_answered(const Phase& p, uint32_t bit_rate) {
    if (uno_) {
      EXPECT_GE(p.busy_share, kMinBusyShare * bit_rate / kBitRate) << "the image did not see that load";
    } else {
      EXPECT_GE(p.flood_bits_per_s, kMinBusyShare * bit_rate) << "the flood was not the load asked";
    }
    EXPECT_TRUE(p.wrong.empty()) << p.wrong.size() << " not answered as documented, first: "
                                 << (p.wrong.empty() ? "" : p.wrong[0]);
    EXPECT_GE(p.own, 10u) << "the master was kept waiting";
    EXPECT_GE(p.remote, kMinUploads) << "the master was kept waiting";
  }

  /// Every heartbeat interval within 1017h + 10 % (on mb2co-node: the
  /// sandbox's allowance).
  void expect_heartbeat_holds(const Phase& p) {
    ASSERT_GT(p.beats.size(), kIntervals) << "heartbeats in the window";
    const uint64_t bound_us = kHeartbeatMs * 1100u;  // +10 %
    size_t over = 0;
    uint64_t shortest = UINT64_MAX, longest = 0;
    for (size_t i = 1; i < p.beats.size(); ++i) {
      // The image's micros() is 32 bits: intervals are taken modulo 2^32.
      const uint64_t gap =
          uno_ ? static_cast<uint32_t>(p.beats[i] - p.beats[i - 1]) : p.beats[i] - p.beats[i - 1];
      shortest = std::min(shortest, gap);
      longest = std::max(longest, gap);
      if (gap > bound_us) {
        ++over;
        std::printf("heartbeat %zu: %llu us after the previous one\n", i,
                    static_cast<unsigned long long>(gap));
      }
    }
    std::printf("heartbeat intervals: %zu, %.1f..%.1f ms (bound %.1f ms)\n", p.beats.size() - 1,
                static_cast<double>(shortest) / 1000.0, static_cast<double>(longest) / 1000.0,
                static_cast<double>(bound_us) / 1000.0);
    RecordProperty("heartbeat_longest_us", std::to_string(longest));
    if (uno_) {
      EXPECT_EQ(over, 0u) << "in the image's own time no interval may pass 1017h + 10 %";
    } else {
      EXPECT_LE(over, kMaxOverBoundOnNode) << over << " intervals beyond " << bound_us << " us";
      EXPECT_LE(longest, kWorstIntervalOnNodeUs);
    }
  }

  /// The share of remote uploads lost (05040000h): at most kMaxLost on the
  /// image (open filters: the chip drops what its loop has no room for),
  /// none on mb2co-node (its kernel filters admit only its ranges).
  void expect_lost_bounded(const Phase& p) {
    const double lost_share =
        p.remote == 0 ? 0.0 : static_cast<double>(p.lost) / static_cast<double>(p.remote);
    RecordProperty("remote_uploads_lost_percent", std::to_string(100.0 * lost_share));
    RecordProperty("frames_dropped_by_the_chip", std::to_string(p.chip_dropped));
    std::printf(
        "remote uploads lost: %.1f %% (bound %.0f %%); frames dropped by the chip: %.1f %%\n",
        100.0 * lost_share, 100.0 * kMaxLost,
        p.chip_in == 0 ? 0.0 : 100.0 * static_cast<double>(p.chip_dropped) / static_cast<double>(p.chip_in));
    if (uno_) {
      EXPECT_LE(lost_share, kMaxLost);
    } else {
      EXPECT_EQ(p.lost, 0u);
    }
  }

  static constexpr CanIdRange kHeartbeat{0x701, kCanRangeExact};
  bool uno_ = false;
  TempDir dir_;
  std::unique_ptr<NodeProcess> gateway_;
  NodeProcess remote_;
  LineChild client_;
  linux_port::SocketCanPort heartbeats_;  ///< the gateway's heartbeats, kernel-stamped (mb2co-node)
};
constexpr CanIdRange UnoNetworkLoad::kHeartbeat;

TEST_F(UnoNetworkLoad, AtFullBusLoadTheHeartbeatHoldsAndEveryRequestIsAnswered) {
  const Phase p = run(kFullLoad);
  expect_answered(p, kFullLoad);
  expect_heartbeat_holds(p);
  expect_lost_bounded(p);
  EXPECT_EQ(ask("write 1 1017 0 6400").rfind("write ", 0), 0u) << "still serving after the flood";
}

TEST_F(UnoNetworkLoad, AtAThirdOfTheBusTheSame) {
  const Phase p = run(kThirdBitRate);
  expect_answered(p, kThirdBitRate);
  expect_heartbeat_holds(p);
  expect_lost_bounded(p);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
