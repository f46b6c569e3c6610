// mb2co-node's heartbeat under a flood of SDO requests to its own id (issue
// 22 item 6). ctest runs this binary inside hil/uml/run-with-vcan.sh (a
// private vcan0; user-mode Linux where the host kernel has no vcan).
//
// The flood: SDO upload requests of 1000h on 600h + id, bursts of 256 by
// sendmmsg, far beyond the ~7,400 frames/s that 1 Mbit/s carries; every one
// the node takes costs it a send (the answer). The flooder and the recorder
// run at nice 19, the node at -10: on a real bus the flood comes from other
// devices, not from the node's CPU (as in load.bus_flood).
//
// What is measured: the node's heartbeats as the bus saw them, i.e. the
// kernel's receive stamps (SO_TIMESTAMP) at a socket of this test. Passes
// when every interval between two heartbeats is at most 1.1 x 1017h (written
// and read back by SDO before the flood) beyond the time the whole machine
// stood still meanwhile. That time comes from a reference: a SCHED_FIFO
// thread of this test that wakes every 2 ms and so runs whenever the
// machine does; a gap of more than 10 ms between its wakeups, less the
// 2 ms, is time in which nothing ran (the host did not run user-mode
// Linux), the node included. (Shorter gaps are not excused: the node's own
// system calls hold the reference off for milliseconds under user-mode
// Linux.)
// More than half the intervals passing only by such an excuse fail the
// test (nothing measured).
#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include "node_harness.h"

namespace mb2co {
namespace test {
namespace {

constexpr auto kUmlDeadline = 60s;  // bounds a failure only
constexpr uint32_t kNodeId = 5;
constexpr uint32_t kSdoRequestId = 0x600 + kNodeId;
constexpr uint32_t kSdoResponseId = 0x580 + kNodeId;
constexpr uint32_t kHeartbeatId = 0x700 + kNodeId;
// Heartbeat intervals measured under the flood (15 s).
constexpr size_t kIntervals = 150;
// 1017h for the test (the default, written so that the test says it).
constexpr uint16_t kPeriodMs = 100;
// Requests per burst of the flooder: one sendmmsg call. Over 1000 overflow
// the kernel's input backlog: frames lost on vcan. A burst of 1024 held the
// whole of user-mode Linux (its kernel is not preemptible) long enough to
// delay the node's heartbeat by 19 ms in a clean-clone CI run, a stall of the
// test's making that no real bus has (frames come one by one); 256 keep the
// flood above 1 Mbit/s (9.1-10.3 k/s measured) without it.
constexpr size_t kBurst = 256;
// Intervals beyond 1017h + 10 % allowed in the window (a scheduler slice of
// the one-CPU sandbox, see the check), and the longest interval allowed.
constexpr size_t kMaxOverBound = 2;
constexpr uint64_t kWorstIntervalUs = 125000;
// The node's bus (500 kbit/s, its default 2000h/2) carries at most ~3,700
// frames/s of 8 data bytes (135 bits with worst-case stuffing): the flood
// must ask for more than that. (1 Mbit/s, ~7,400/s, is what the one-CPU
// sandbox reaches at best: the flooders only run while the node waits, so
// the flood settles at what the node answers, 7.3-10 k/s measured.)
constexpr double kMinRequestsPerS = 3700.0;
// The node must have been busy answering: under user-mode Linux it answers
// 10,000-36,000 requests/s (each answer is a system call of 16-100 us).
constexpr double kMinAnswersPerS = 3000.0;
// The reference wakes every kReferencePeriodUs; a gap beyond
// kReferenceStallUs is a stall of the whole machine, counted beyond one period.
constexpr uint64_t kReferencePeriodUs = 2000;
constexpr uint64_t kReferenceStallUs = 10000;
// Priorities (nice) of the node and of this test's flooder and recorder.
constexpr int kNodeNice = -10;
constexpr int kFloodNice = 19;
constexpr int kFlooders = 2;

uint64_t realtime_us() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

void nice_this_thread(int value) {
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), value);
}

/// A CAN_RAW socket on vcan0 receiving exactly the standard data frames
/// `ids` (none: receives nothing), or with `all_but` every frame except
/// those, with kernel receive stamps and a large receive buffer.
class CanSocket {
 public:
  explicit CanSocket(const std::vector<uint32_t>& ids, bool all_but = false) {
    fd_ = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (fd_ < 0) return;
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(if_nametoindex("vcan0"));
    std::vector<can_filter> filters;
    for (uint32_t id : ids) {
      filters.push_back({all_but ? id | CAN_INV_FILTER : id, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG});
    }
    const int on = 1, rcvbuf = 8 << 20;
    if (bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        (all_but && setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_JOIN_FILTERS, &on, sizeof on) != 0) ||
        setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters.empty() ? nullptr : filters.data(),
                   static_cast<socklen_t>(filters.size() * sizeof(can_filter))) != 0 ||
        setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMP, &on, sizeof on) != 0 ||
        setsockopt(fd_, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) != 0 ||
        setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf, sizeof rcvbuf) != 0) {
      close(fd_);
      fd_ = -1;
    }
  }
  ~CanSocket() {
    if (fd_ >= 0) close(fd_);
  }
  CanSocket(const CanSocket&) = delete;
  CanSocket& operator=(const CanSocket&) = delete;
  int fd() const { return fd_; }

  /// Frames the kernel dropped for a full receive buffer (SO_RXQ_OVFL).
  uint32_t dropped() const { return dropped_; }

  /// Takes up to kBatch waiting frames with their kernel receive stamps
  /// (µs, wall clock), without waiting; how many.
  static constexpr size_t kBatch = 64;
  size_t receive(can_frame* frames, uint64_t* stamps_us) {
    iovec iov[kBatch];
    mmsghdr msgs[kBatch];
    alignas(cmsghdr) char control[kBatch][CMSG_SPACE(sizeof(timeval)) + CMSG_SPACE(sizeof(uint32_t))];
    memset(msgs, 0, sizeof msgs);
    for (size_t i = 0; i < kBatch; ++i) {
      iov[i] = iovec{&frames[i], sizeof frames[i]};
      msgs[i].msg_hdr.msg_iov = &iov[i];
      msgs[i].msg_hdr.msg_iovlen = 1;
      msgs[i].msg_hdr.msg_control = control[i];
      msgs[i].msg_hdr.msg_controllen = sizeof control[i];
    }
    const int got = recvmmsg(fd_, msgs, kBatch, MSG_DONTWAIT, nullptr);
    for (int i = 0; i < got; ++i) {
      stamps_us[i] = 0;  // no stamp: the test fails on it below
      for (cmsghdr* c = CMSG_FIRSTHDR(&msgs[i].msg_hdr); c != nullptr; c = CMSG_NXTHDR(&msgs[i].msg_hdr, c)) {
        if (c->cmsg_level != SOL_SOCKET) continue;
        if (c->cmsg_type == SCM_TIMESTAMP) {
          timeval tv{};
          memcpy(&tv, CMSG_DATA(c), sizeof tv);
          stamps_us[i] = static_cast<uint64_t>(tv.tv_sec) * 1000000u + static_cast<uint64_t>(tv.tv_usec);
        } else if (c->cmsg_type == SO_RXQ_OVFL) {
          memcpy(&dropped_, CMSG_DATA(c), sizeof dropped_);
        }
      }
    }
    return got > 0 ? static_cast<size_t>(got) : 0;
  }

 private:
  int fd_ = -1;
  uint32_t dropped_ = 0;
};

/// Frames vcan0 has carried since it was created (each frame sent counts
/// once, whoever receives it); 0 when unreadable.
uint64_t frames_on_bus() {
  std::FILE* f = std::fopen("/sys/class/net/vcan0/statistics/tx_packets", "r");
  unsigned long long n = 0;
  if (f != nullptr) {
    if (std::fscanf(f, "%llu", &n) != 1) n = 0;
    std::fclose(f);
  }
  return n;
}

/// Frames the kernel dropped for a full input backlog (all CPUs), the
/// second column of /proc/net/softnet_stat: on vcan that is a frame lost
/// on the "bus" after its sender's send succeeded.
uint64_t backlog_drops() {
  std::FILE* f = std::fopen("/proc/net/softnet_stat", "r");
  uint64_t sum = 0;
  unsigned processed = 0, dropped = 0;
  if (f == nullptr) return 0;
  char line[512];
  while (std::fgets(line, sizeof line, f) != nullptr) {
    if (std::sscanf(line, "%x %x", &processed, &dropped) == 2) sum += dropped;
  }
  std::fclose(f);
  return sum;
}

/// One expedited SDO transfer with the node (before the flood): `request`
/// (command byte, index, subindex, data) on 600h + id; the response's 8
/// bytes, or an empty vector when none came.
std::vector<uint8_t> sdo_exchange(const std::vector<uint8_t>& request) {
  CanSocket bus({kSdoResponseId});
  can_frame frame{};
  frame.can_id = kSdoRequestId;
  frame.len = 8;
  std::copy(request.begin(), request.end(), frame.data);
  if (write(bus.fd(), &frame, sizeof frame) != static_cast<ssize_t>(sizeof frame)) return {};
  can_frame frames[CanSocket::kBatch];
  uint64_t stamps[CanSocket::kBatch];
  for (const auto deadline = std::chrono::steady_clock::now() + kUmlDeadline;
       std::chrono::steady_clock::now() < deadline;) {
    pollfd p{bus.fd(), POLLIN, 0};
    poll(&p, 1, 100);
    const size_t got = bus.receive(frames, stamps);
    // The response to this request: same index and subindex.
    for (size_t i = 0; i < got; ++i) {
      if (frames[i].data[1] == request[1] && frames[i].data[2] == request[2] &&
          frames[i].data[3] == request[3])
        return std::vector<uint8_t>(frames[i].data, frames[i].data + 8);
    }
  }
  return {};
}

/// What the threads below collect while the flood runs.
struct Record {
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<uint64_t> heartbeats_us;  ///< bus stamps of the node's heartbeats
  uint64_t others = 0;                  ///< frames neither heartbeat, SDO request nor response
  uint64_t requests = 0;                ///< SDO requests the flooder queued
  std::vector<uint64_t> reference_us;   ///< the reference's wakeups (wall clock)
  bool missing_stamp = false;
};

/// Stall time of the whole machine within [from_us, to_us]: the part of
/// every reference gap longer than kReferenceStallUs beyond one period.
uint64_t stalled_us(const std::vector<uint64_t>& reference_us, uint64_t from_us, uint64_t to_us) {
  uint64_t stalled = 0;
  for (size_t j = 1; j < reference_us.size(); ++j) {
    const uint64_t a = std::max(reference_us[j - 1], from_us), b = std::min(reference_us[j], to_us);
    if (reference_us[j] - reference_us[j - 1] <= kReferenceStallUs || b <= a) continue;
    if (b - a > kReferencePeriodUs) stalled += b - a - kReferencePeriodUs;
  }
  return stalled;
}

TEST(SdoFlood, HeartbeatKeepsItsPeriod) {
  TempDir dir;
  NodeProcess node;
  const std::vector<std::string> args{"--can", "vcan0",          "--node-id", std::to_string(kNodeId),
                                      "--pty", dir.path("n.pty")};
  nice_this_thread(kNodeNice);  // the node inherits it
  const bool started = node.start(args, kUmlDeadline);
  nice_this_thread(0);
  ASSERT_TRUE(started) << node.error();
  nice_this_thread(0);
  // 1017h = kPeriodMs, written and read back by SDO.
  const std::vector<uint8_t> written = sdo_exchange(
      {0x2B, 0x17, 0x10, 0x00, static_cast<uint8_t>(kPeriodMs), static_cast<uint8_t>(kPeriodMs >> 8)});
  ASSERT_EQ(written.size(), 8u) << "no answer to the write of 1017h";
  ASSERT_EQ(written[0], 0x60) << "1017h write refused";
  const std::vector<uint8_t> read = sdo_exchange({0x40, 0x17, 0x10, 0x00});
  ASSERT_EQ(read.size(), 8u) << "no answer to the read of 1017h";
  ASSERT_EQ(read[0], 0x4B) << "1017h read refused";
  const int period_ms = read[4] | (read[5] << 8);
  ASSERT_EQ(period_ms, static_cast<int>(kPeriodMs));
  // Every frame but the flood and its answers: the heartbeats and the
  // node's few other frames. The answers are not read here (that would
  // take the CPU the node needs): the bus's frame count less the requests
  // and these frames is their number.
  CanSocket heartbeats({kSdoRequestId, kSdoResponseId}, true);
  CanSocket flooder({});
  ASSERT_GE(heartbeats.fd(), 0) << "socket on vcan0";
  ASSERT_GE(flooder.fd(), 0) << "socket on vcan0";
  const uint64_t bound_us = static_cast<uint64_t>(period_ms) * 1100u;  // +10 %

  Record rec;
  rec.reference_us.reserve(1 << 20);
  std::atomic<bool> stop{false};
  // The reference: at the highest priority, it runs whenever the machine does.
  std::thread reference([&] {
    sched_param prio{};
    prio.sched_priority = sched_get_priority_max(SCHED_FIFO);
    if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &prio) != 0) {
      std::lock_guard<std::mutex> lock(rec.mutex);
      rec.reference_us.clear();  // checked below: no reference, no result
      return;
    }
    const timespec period{0, static_cast<long>(kReferencePeriodUs) * 1000};
    std::vector<uint64_t> wakeups;
    wakeups.reserve(1 << 20);
    while (!stop) {
      wakeups.push_back(realtime_us());
      clock_nanosleep(CLOCK_MONOTONIC, 0, &period, nullptr);
    }
    std::lock_guard<std::mutex> lock(rec.mutex);
    rec.reference_us.swap(wakeups);
  });
  std::thread record([&] {
    nice_this_thread(kFloodNice);
    can_frame frames[CanSocket::kBatch];
    uint64_t stamps[CanSocket::kBatch];
    while (!stop) {
      pollfd p{heartbeats.fd(), POLLIN, 0};
      poll(&p, 1, 50);
      const size_t got = heartbeats.receive(frames, stamps);
      std::lock_guard<std::mutex> lock(rec.mutex);
      for (size_t i = 0; i < got; ++i) {
        if (frames[i].can_id != kHeartbeatId) {
          ++rec.others;
          continue;
        }
        if (stamps[i] == 0) rec.missing_stamp = true;
        rec.heartbeats_us.push_back(stamps[i]);
      }
      if (got != 0) rec.changed.notify_all();
    }
  });
  const uint64_t bus_from = frames_on_bus();
  const uint64_t backlog_drops_from = backlog_drops();
  const uint64_t flood_from_us = realtime_us();
  // kFlooders threads: each nice-19 thread gets a small share of the one CPU,
  // and with bursts of 256 one alone asked for 7.3-10 k requests/s, at times
  // below what 1 Mbit/s carries; two keep the flood above it.
  auto flood_body = [&] {
    nice_this_thread(kFloodNice);
    std::vector<can_frame> frames(kBurst);
    std::vector<iovec> iov(kBurst);
    std::vector<mmsghdr> msgs(kBurst);
    for (size_t i = 0; i < kBurst; ++i) {
      frames[i] = can_frame{};
      frames[i].can_id = kSdoRequestId;
      frames[i].len = 8;
      frames[i].data[0] = 0x40;  // upload 1000h/0
      frames[i].data[2] = 0x10;
      iov[i] = iovec{&frames[i], sizeof frames[i]};
      msgs[i] = mmsghdr{};
      msgs[i].msg_hdr.msg_iov = &iov[i];
      msgs[i].msg_hdr.msg_iovlen = 1;
    }
    uint64_t sent = 0;
    while (!stop) {
      const int queued = sendmmsg(flooder.fd(), msgs.data(), static_cast<unsigned>(kBurst), MSG_DONTWAIT);
      if (queued > 0) sent += static_cast<uint64_t>(queued);
      // Without it a nice-19 thread, once picked, keeps the CPU until the
      // next tick (10 ms under user-mode Linux): the node's own CPU.
      sched_yield();
    }
    std::lock_guard<std::mutex> lock(rec.mutex);
    rec.requests += sent;
  };
  std::thread flood[kFlooders];
  for (std::thread& f : flood) f = std::thread(flood_body);
  // The window: until kIntervals + 1 heartbeats came after the flood began.
  {
    std::unique_lock<std::mutex> lock(rec.mutex);
    rec.changed.wait_for(lock, kUmlDeadline, [&] {
      return std::count_if(rec.heartbeats_us.begin(), rec.heartbeats_us.end(),
                           [&](uint64_t t) { return t >= flood_from_us; }) > static_cast<long>(kIntervals);
    });
  }
  const uint64_t flood_to_us = realtime_us();
  stop = true;
  for (std::thread& f : flood) f.join();
  record.join();
  reference.join();

  ASSERT_FALSE(rec.missing_stamp) << "a heartbeat without SO_TIMESTAMP";
  ASSERT_EQ(heartbeats.dropped(), 0u) << "heartbeats lost in this test's receive buffer";
  ASSERT_FALSE(rec.reference_us.empty()) << "the reference thread could not get SCHED_FIFO";
  const uint64_t on_bus = frames_on_bus() - bus_from;
  EXPECT_EQ(backlog_drops() - backlog_drops_from, 0u) << "frames lost on vcan (kernel input backlog)";
  const uint64_t answers = on_bus - std::min(on_bus, rec.requests + rec.heartbeats_us.size() + rec.others);
  const double seconds = static_cast<double>(flood_to_us - flood_from_us) / 1e6;
  const double requests_per_s = static_cast<double>(rec.requests) / seconds;
  const double answers_per_s = static_cast<double>(answers) / seconds;
  std::printf("flood: %.1f s, %.0f SDO requests/s sent, %.0f answered/s; bound %llu us\n", seconds,
              requests_per_s, answers_per_s, static_cast<unsigned long long>(bound_us));
  EXPECT_GE(requests_per_s, kMinRequestsPerS) << "the flood asked for less than the node's bus carries";
  EXPECT_GE(answers_per_s, kMinAnswersPerS) << "the node was not kept busy";

  std::vector<uint64_t> hb;
  for (uint64_t t : rec.heartbeats_us)
    if (t >= flood_from_us && t <= flood_to_us) hb.push_back(t);
  ASSERT_GT(hb.size(), kIntervals) << "heartbeats in the window";
  size_t excused = 0;  // intervals within the bound only thanks to a stall
  size_t over = 0;     // intervals beyond the bound (beyond stalls)
  uint64_t shortest_us = UINT64_MAX, worst_us = 0, worst_beyond_stall_us = 0;
  for (size_t i = 1; i < hb.size(); ++i) {
    ASSERT_GE(hb[i], hb[i - 1]) << "bus stamps in order";
    const uint64_t gap_us = hb[i] - hb[i - 1];
    const uint64_t stall_us = stalled_us(rec.reference_us, hb[i - 1], hb[i]);
    const uint64_t beyond_stall_us = gap_us > stall_us ? gap_us - stall_us : 0;
    if (gap_us > bound_us && beyond_stall_us <= bound_us) ++excused;
    shortest_us = std::min(shortest_us, gap_us);
    worst_us = std::max(worst_us, gap_us);
    worst_beyond_stall_us = std::max(worst_beyond_stall_us, beyond_stall_us);
    if (beyond_stall_us > bound_us) {
      ++over;
      std::printf("heartbeat %zu: %llu us after the previous one, the machine stood still %llu us of it\n", i,
                  static_cast<unsigned long long>(gap_us), static_cast<unsigned long long>(stall_us));
    }
  }
  // The sandbox is one CPU of user-mode Linux shared with the flooder: a
  // scheduler slice (10 ms) can hold any process up once in a while (clean-
  // clone CI runs of the fixed node: 0-2 of 150 intervals over 110 ms, at most
  // 118.9 ms). The loop that handed in 128 frames before process() had 22-28
  // of 150 over, up to 130 ms; the 442 ms was beyond any consumer.
  EXPECT_LE(over, kMaxOverBound) << over << " of " << hb.size() - 1 << " intervals beyond " << bound_us
                                 << " us";
  EXPECT_LE(worst_beyond_stall_us, kWorstIntervalUs) << "a heartbeat interval beyond any sandbox hiccup";
  std::printf(
      "heartbeat intervals: %zu, %.1f..%.1f ms, longest beyond stalls %.1f ms, %zu within the bound "
      "only by a stall\n",
      hb.size() - 1, static_cast<double>(shortest_us) / 1000.0, static_cast<double>(worst_us) / 1000.0,
      static_cast<double>(worst_beyond_stall_us) / 1000.0, excused);
  EXPECT_LE(excused * 2, hb.size() - 1) << "the machine stood still in most intervals: nothing measured";
  EXPECT_EQ(node.stop(), 0) << node.child.stderr_text();
}

}  // namespace
}  // namespace test
}  // namespace mb2co
