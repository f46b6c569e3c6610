// SocketCanPort against independent peers on virtual CAN: candump/cansend
// (can-utils) and python3-can. Needs vcan0 and vcan1 and root (tc, ip):
// ctest runs it as `hil/uml/run-with-vcan.sh --ifaces vcan0,vcan1 -- THIS`.
// Synchronisation is by what peers print (READY, SENT, a probe frame seen),
// never by sleeping; timeouts below only bound a failure.
#include <gtest/gtest.h>
#include <poll.h>
#include <string.h>
#include <time.h>

#include <chrono>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "can_text.h"
#include "line_child.h"
#include "platform/socketcan_port.h"

namespace {

using mb2co::CanFrame;
using mb2co::CanIdRange;
using mb2co::CanSink;
using mb2co::kCanRangeExact;
using mb2co::kCanRangeRemote;
using mb2co::Status;
using mb2co::linux_port::CanAcceptance;
using mb2co::linux_port::IoPath;
using mb2co::linux_port::SocketCanPort;
using mb2co::linux_port::TimedCanFrame;
using mb2co::test::candump_frame_field;
using mb2co::test::LineChild;
using mb2co::test::make_frame;
using mb2co::test::same_frame;
using mb2co::test::to_text;
using std::chrono::milliseconds;

// A Status as a gtest result: its message when it failed.
::testing::AssertionResult done(const Status& s) {
  return s ? ::testing::AssertionSuccess() : ::testing::AssertionFailure() << s.message();
}

constexpr char kBus[] = "vcan0";             // where the peers listen and talk
constexpr char kSpare[] = "vcan1";           // taken down / plugged by the transmit tests
constexpr milliseconds kPeerTimeout{30000};  // python3 needs ~2 s to start under user-mode Linux
constexpr uint8_t kExt = CanFrame::kExtended;
constexpr uint8_t kRtr = CanFrame::kRtr;

// Standard, extended, RTR, dlc 0 and 8.
std::vector<CanFrame> assorted_frames() {
  return {
      make_frame(0x000, 0, 0),
      make_frame(0x123, 0, 8, "1122334455667788"),
      make_frame(0x7FF, 0, 3, "A1B2C3"),
      make_frame(0x1FFFFFFF, kExt, 8, "0102030405060708"),
      make_frame(0x001, kExt, 1, "AA"),  // extended although the id would fit 11 bits
      make_frame(0x456, kRtr, 0),
      make_frame(0x181, kRtr, 8),
      make_frame(0x1234567, kRtr | kExt, 3),
  };
}

std::vector<std::string> texts(const std::vector<CanFrame>& frames) {
  std::vector<std::string> out;
  for (const CanFrame& f : frames) out.push_back(to_text(f));
  return out;
}

std::vector<std::string> texts(const std::vector<TimedCanFrame>& frames) {
  std::vector<std::string> out;
  for (const TimedCanFrame& f : frames) out.push_back(to_text(f.frame));
  return out;
}

std::string joined(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += " " + w;
  return out;
}

uint64_t monotonic_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

// Waits (poll on fd()) until `count` frames are in, or `timeout_ms` passes.
std::vector<TimedCanFrame> receive_frames(SocketCanPort& port, size_t count,
                                          milliseconds timeout = kPeerTimeout) {
  std::vector<TimedCanFrame> got;
  const uint64_t deadline = monotonic_us() + static_cast<uint64_t>(timeout.count()) * 1000u;
  while (got.size() < count) {
    TimedCanFrame batch[SocketCanPort::kBatch];
    const size_t wanted = count - got.size();
    const size_t n = port.receive(batch, wanted < SocketCanPort::kBatch ? wanted : SocketCanPort::kBatch);
    got.insert(got.end(), batch, batch + n);
    if (n > 0) continue;
    const uint64_t now = monotonic_us();
    if (now >= deadline) break;
    pollfd p{port.fd(), POLLIN, 0};
    poll(&p, 1, static_cast<int>((deadline - now) / 1000u) + 1);
  }
  return got;
}

bool any_line(const std::string&) {
  return true;
}

// Runs a command to completion: its exit code (stderr echoed on failure).
int run_command(const std::vector<std::string>& argv) {
  LineChild child;
  if (!child.start(argv)) return -1;
  child.close_stdin();
  const int code = child.wait_exit(kPeerTimeout);
  if (code != 0) std::cerr << argv[0] << ": " << child.stderr_text();
  return code;
}

// The python3-can peer (tests/vcan/can_peer.py), started and bound.
class PythonPeer {
 public:
  bool start(const char* iface) {
    return child_.start({MB2CO_VCAN_PYTHON, MB2CO_CAN_PEER_PY, iface}) &&
           child_.wait_prefix("READY", kPeerTimeout);
  }
  bool send(const std::vector<CanFrame>& frames) {
    return child_.send_line("send" + joined(texts(frames))) &&
           child_.wait_line(
               [&](const std::string& l) { return l == "SENT " + std::to_string(frames.size()); },
               kPeerTimeout);
  }
  // What it received, in order, in can-utils notation.
  std::vector<std::string> receive(size_t count) {
    std::vector<std::string> got;
    std::string line;
    if (!child_.send_line("recv " + std::to_string(count))) return got;
    while (child_.wait_line(any_line, kPeerTimeout, &line) && line != "DONE") {
      if (line.rfind("FRAME ", 0) == 0) got.push_back(line.substr(6));
    }
    return got;
  }
  int quit() {
    child_.send_line("quit");
    child_.close_stdin();
    const int code = child_.wait_exit(kPeerTimeout);
    if (code != 0) std::cerr << "can_peer.py: " << child_.stderr_text();
    return code;
  }

 private:
  LineChild child_;
};

// Runs a shell-level cleanup when the test leaves, pass or fail.
struct Cleanup {
  std::vector<std::string> argv;
  ~Cleanup() { run_command(argv); }
};

class SocketCanVcan : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(done(port_.open(kBus))); }
  SocketCanPort port_;
};

TEST(SocketCanOpen, MissingInterfaceGivesOneLineError) {
  SocketCanPort port;
  const Status opened = port.open("vcan9");
  EXPECT_FALSE(opened);
  EXPECT_FALSE(port.is_open());
  EXPECT_EQ(port.fd(), -1);
  EXPECT_NE(strstr(opened.message().c_str(), "vcan9"), nullptr) << opened.message();
  EXPECT_NE(strstr(opened.message().c_str(), "no such interface"), nullptr) << opened.message();
  EXPECT_EQ(strchr(opened.message().c_str(), '\n'), nullptr);
}

TEST(SocketCanOpen, NonCanInterfaceIsRefused) {
  SocketCanPort port;
  const Status opened = port.open("lo");
  EXPECT_FALSE(opened);
  EXPECT_NE(strstr(opened.message().c_str(), "not a CAN interface"), nullptr) << opened.message();
}

TEST_F(SocketCanVcan, RaisesTheReceiveBuffer) {
  // Root (as inside the sandbox) may exceed rmem_max; the kernel reports double.
  EXPECT_GE(port_.rcvbuf_bytes(), SocketCanPort::kDefaultRcvbufBytes);
  EXPECT_GE(port_.fd(), 0);
}

TEST_F(SocketCanVcan, CandumpSeesWhatWeSendAlsoThroughTheSink) {
  LineChild dump;
  ASSERT_TRUE(dump.start({"stdbuf", "-o0", "candump", "-L", kBus})) << dump.error();
  // candump binds some time after it starts: repeat a probe until it shows.
  const CanFrame probe = make_frame(0x7FE, 0, 1, "A5");
  const std::string probe_text = to_text(probe);
  bool ready = false;
  std::string line;
  for (int attempt = 0; attempt < 600 && !ready; ++attempt) {
    ASSERT_TRUE(port_.send(probe)) << port_.last_io_error();
    ready = dump.wait_line([&](const std::string& l) { return candump_frame_field(l) == probe_text; },
                           milliseconds(50));
  }
  ASSERT_TRUE(ready) << "candump never showed the probe frame";

  const std::vector<CanFrame> frames = assorted_frames();
  const CanSink sink = port_.sink();
  for (size_t i = 0; i < frames.size(); ++i) {
    const bool sent = i % 2 == 0 ? port_.send(frames[i]) : sink.send(sink.ctx, frames[i]);
    ASSERT_TRUE(sent) << port_.last_io_error();
  }
  std::vector<std::string> seen;
  while (seen.size() < frames.size() && dump.wait_line(any_line, kPeerTimeout, &line)) {
    const std::string field = candump_frame_field(line);
    if (field != probe_text) seen.push_back(field);
  }
  EXPECT_EQ(seen, texts(frames));
  EXPECT_EQ(port_.counters().tx_dropped, 0u);
  EXPECT_EQ(port_.counters().tx_errors, 0u);
}

TEST_F(SocketCanVcan, PythonCanSeesWhatWeSendInOneBatch) {
  PythonPeer peer;
  ASSERT_TRUE(peer.start(kBus));
  const std::vector<CanFrame> frames = assorted_frames();
  EXPECT_EQ(port_.send(frames.data(), frames.size()), frames.size()) << port_.last_io_error();
  EXPECT_EQ(port_.counters().tx_frames, frames.size());
  EXPECT_EQ(peer.receive(frames.size()), texts(frames));
  EXPECT_EQ(peer.quit(), 0);
}

void expect_received(const std::vector<CanFrame>& sent, const std::vector<TimedCanFrame>& got,
                     uint64_t t_before_us, uint64_t t_after_us) {
  ASSERT_EQ(texts(got), texts(sent));
  uint64_t previous_us = t_before_us;
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_TRUE(same_frame(got[i].frame, sent[i])) << to_text(sent[i]);
    if (got[i].frame.rtr()) {
      const uint8_t zeros[8] = {};
      EXPECT_EQ(memcmp(got[i].frame.data, zeros, 8), 0) << "RTR data not zeroed";
    }
    EXPECT_GE(got[i].rx_time_us, previous_us) << "timestamps out of order at " << i;
    EXPECT_LE(got[i].rx_time_us, t_after_us);
    previous_us = got[i].rx_time_us;
  }
}

TEST_F(SocketCanVcan, ReceivesFramesFromCansend) {
  const std::vector<CanFrame> frames = assorted_frames();
  const uint64_t before_us = monotonic_us();
  uint64_t last_send_us = 0;
  for (const CanFrame& f : frames) {
    last_send_us = monotonic_us();
    ASSERT_EQ(run_command({"cansend", kBus, to_text(f)}), 0) << to_text(f);
  }
  const std::vector<TimedCanFrame> got = receive_frames(port_, frames.size());
  expect_received(frames, got, before_us, monotonic_us());
  EXPECT_EQ(port_.counters().rx_frames, frames.size());
  // Kernel receive time (SO_TIMESTAMP), not the time we read: the first frame
  // was queued before the last cansend started, and read after it ended.
  ASSERT_FALSE(got.empty());
  EXPECT_LT(got[0].rx_time_us, last_send_us);
}

TEST_F(SocketCanVcan, ReceivesFramesFromPythonCan) {
  PythonPeer peer;
  ASSERT_TRUE(peer.start(kBus));
  const std::vector<CanFrame> frames = assorted_frames();
  const uint64_t before_us = monotonic_us();
  ASSERT_TRUE(peer.send(frames));
  const std::vector<TimedCanFrame> got = receive_frames(port_, frames.size());
  expect_received(frames, got, before_us, monotonic_us());
  EXPECT_EQ(peer.quit(), 0);
}

TEST_F(SocketCanVcan, KernelFiltersPassOnlyListedFrames) {
  const CanAcceptance filters[] = {
      CanAcceptance::exact(0x181),
      CanAcceptance::exact(0x1234567, true),
      {0x700, 0x780, false},  // 0x700..0x77F
  };
  ASSERT_TRUE(done(port_.set_filters(filters, 3)));
  const CanFrame marker = make_frame(0x181, 0, 1, "FF");  // passes; everything before it has arrived then
  const std::vector<CanFrame> offered = {
      make_frame(0x181, 0, 1, "01"),  make_frame(0x181, kExt, 1, "02"),  // extended 0x181: other format
      make_frame(0x182, 0, 1, "03"),  make_frame(0x1234567, kExt, 1, "04"),
      make_frame(0x1234568, kExt, 0), make_frame(0x701, kRtr, 2),  // RTR passes like data
      make_frame(0x77F, 0, 1, "06"),  make_frame(0x780, 0, 1, "07"),
      make_frame(0x567, 0, 1, "08"),  marker,
  };
  const std::vector<CanFrame> passing = {offered[0], offered[3], offered[5], offered[6], marker};
  PythonPeer peer;
  ASSERT_TRUE(peer.start(kBus));
  ASSERT_TRUE(peer.send(offered));
  std::vector<TimedCanFrame> got = receive_frames(port_, passing.size());
  EXPECT_EQ(texts(got), texts(passing));

  // Back to everything: a frame the filters kept out now arrives.
  ASSERT_TRUE(done(port_.accept_all()));
  ASSERT_TRUE(peer.send({offered[2]}));
  got = receive_frames(port_, 1);
  EXPECT_EQ(texts(got), texts(std::vector<CanFrame>{offered[2]}));
  EXPECT_EQ(peer.quit(), 0);
}

// The core's filter callback (CanControl::set_filters at reset, the ranges
// of Node::acceptance): exact ids, every standard RTR (the node answers
// RTRs for its TPDOs) and a network service's 580h-5FFh; a flood of
// anything else, extended frames included, stays in the kernel.
TEST_F(SocketCanVcan, CoreFiltersPassWhatTheRangesAdmit) {
  const CanIdRange ranges[] = {{0x000, kCanRangeExact}, {0x080, kCanRangeExact},
                               {0x605, kCanRangeExact}, {0x705, kCanRangeExact},
                               {0x580, 0x780},          {kCanRangeRemote, kCanRangeRemote}};
  SocketCanPort::kControl.set_filters(&port_, ranges, 6);
  EXPECT_STREQ(port_.last_io_error(), "");
  const CanFrame marker = make_frame(0x605, 0, 1, "FF");  // passes; everything before it has arrived then
  const std::vector<CanFrame> offered = {
      make_frame(0x000, 0, 2, "0105"),  make_frame(0x124, 0, 1, "01"),    make_frame(0x080, 0, 0),
      make_frame(0x605, kExt, 1, "02"), make_frame(0x185, kRtr, 8),       make_frame(0x185, kExt | kRtr, 8),
      make_frame(0x705, kRtr, 0),       make_frame(0x7FF, 0, 1, "03"),    make_frame(0x5A3, 0, 1, "04"),
      make_frame(0x600, 0, 1, "05"),    make_frame(0x580, kExt, 1, "06"), marker,
  };
  const std::vector<CanFrame> passing = {offered[0], offered[2], offered[4], offered[6], offered[8], marker};
  PythonPeer peer;
  ASSERT_TRUE(peer.start(kBus));
  ASSERT_TRUE(peer.send(offered));
  EXPECT_EQ(texts(receive_frames(port_, passing.size())), texts(passing));
  EXPECT_EQ(peer.quit(), 0);
}

// The remote bit of a range (kCanRangeRemote) is the kernel's RTR flag:
// with it in the mask, a range takes only data or only remote frames.
TEST_F(SocketCanVcan, RangesTellDataFromRemoteFrames) {
  const uint16_t kBoth = kCanRangeExact | kCanRangeRemote;
  const CanIdRange ranges[] = {{0x181, kBoth}, {0x281 | kCanRangeRemote, kBoth}};
  ASSERT_TRUE(done(port_.set_ranges(ranges, 2)));
  const CanFrame marker = make_frame(0x181, 0, 1, "FF");
  const std::vector<CanFrame> offered = {
      make_frame(0x181, 0, 1, "01"),
      make_frame(0x181, kRtr, 1),
      make_frame(0x281, 0, 1, "02"),
      make_frame(0x281, kRtr, 2),
      marker,
  };
  const std::vector<CanFrame> passing = {offered[0], offered[3], marker};
  PythonPeer peer;
  ASSERT_TRUE(peer.start(kBus));
  ASSERT_TRUE(peer.send(offered));
  EXPECT_EQ(texts(receive_frames(port_, passing.size())), texts(passing));
  EXPECT_EQ(peer.quit(), 0);
}

TEST_F(SocketCanVcan, EmptyFilterListReceivesNothing) {
  SocketCanPort witness;  // sees every frame: tells when the burst is through
  ASSERT_TRUE(done(witness.open(kBus)));
  ASSERT_TRUE(done(port_.set_filters(nullptr, 0)));
  const std::vector<CanFrame> frames = assorted_frames();
  PythonPeer peer;
  ASSERT_TRUE(peer.start(kBus));
  ASSERT_TRUE(peer.send(frames));
  EXPECT_EQ(receive_frames(witness, frames.size()).size(), frames.size());
  pollfd p{port_.fd(), POLLIN, 0};
  EXPECT_EQ(poll(&p, 1, 0), 0);
  TimedCanFrame any;
  EXPECT_FALSE(port_.receive(any));
  EXPECT_EQ(peer.quit(), 0);
}

TEST_F(SocketCanVcan, BadFiltersAreRefused) {
  const CanAcceptance too_big = CanAcceptance::exact(0x800);  // 12 bits in a standard id
  const Status refused = port_.set_filters(&too_big, 1);
  EXPECT_FALSE(refused);
  EXPECT_NE(strstr(refused.message().c_str(), "out of range"), nullptr) << refused.message();
  std::vector<CanAcceptance> many(513, CanAcceptance::exact(1));
  EXPECT_FALSE(port_.set_filters(many.data(), many.size()));
}

// A flood on a reader that does not read: what its buffers cannot hold is
// dropped and counted, nothing grows; on kRing the ring's own buffers take
// their share first.
void expect_overflow_counted(SocketCanPort& sender, IoPath path) {
  SocketCanPort slow;  // smallest buffer the kernel allows: holds a few frames
  ASSERT_TRUE(done(slow.open(kBus, 1, path)));
  ASSERT_EQ(slow.io_path(), path) << slow.io_note();
  SocketCanPort witness;  // big buffer: tells when the kernel has delivered the flood
  ASSERT_TRUE(done(witness.open(kBus)));
  std::vector<CanFrame> flood;
  for (uint32_t i = 0; i < 500; ++i) flood.push_back(make_frame(0x100 + (i & 0xFF), 0, 2, "0000"));
  ASSERT_EQ(sender.send(flood.data(), flood.size()), flood.size()) << sender.last_io_error();
  // More frames than one softirq run delivers: some are still in flight when
  // send returns. Once the witness has them all, `slow` has had its chance.
  ASSERT_EQ(receive_frames(witness, flood.size()).size(), flood.size());
  EXPECT_EQ(witness.counters().rx_dropped, 0u);
  // Drain what `slow` kept, then a marker: it carries the kernel's drop count.
  size_t kept = receive_frames(slow, flood.size(), milliseconds(0)).size();
  const CanFrame marker = make_frame(0x7FD, 0, 0);
  ASSERT_TRUE(sender.send(marker));
  for (;;) {
    const std::vector<TimedCanFrame> next = receive_frames(slow, 1);
    ASSERT_EQ(next.size(), 1u) << "marker lost";
    if (next[0].frame.id == marker.id) break;
    ++kept;  // on SMP the last flood frame may reach `slow` just after the witness
  }
  EXPECT_GT(slow.counters().rx_dropped, 0u);
  EXPECT_EQ(kept + slow.counters().rx_dropped, flood.size());
  EXPECT_EQ(slow.counters().rx_frames, kept + 1);
}

TEST_F(SocketCanVcan, ReceiveOverflowIsCounted) {
  expect_overflow_counted(port_, IoPath::kCalls);
}

TEST_F(SocketCanVcan, ReceiveOverflowIsCountedOnTheRing) {
  expect_overflow_counted(port_, IoPath::kRing);
}

TEST_F(SocketCanVcan, RingTakesAFloodInOrderWhenItReadsAgain) {
  SocketCanPort ring;
  ASSERT_TRUE(done(ring.open(kBus, SocketCanPort::kDefaultRcvbufBytes, IoPath::kRing)));
  ASSERT_EQ(ring.io_path(), IoPath::kRing) << ring.io_note();
  // Far more than the ring's buffers while it does not read: the socket's
  // buffer keeps the rest until the receive is armed again.
  std::vector<CanFrame> flood;
  char hex[5];
  for (uint32_t i = 0; i < 1000; ++i) {
    snprintf(hex, sizeof hex, "%04X", i);
    flood.push_back(make_frame(0x200 + (i & 0xFF), 0, 2, hex));
  }
  ASSERT_EQ(port_.send(flood.data(), flood.size()), flood.size()) << port_.last_io_error();
  const std::vector<TimedCanFrame> got = receive_frames(ring, flood.size());
  EXPECT_EQ(texts(got), texts(flood));
  EXPECT_EQ(ring.counters().rx_dropped, 0u);
  EXPECT_EQ(ring.counters().io_errors, 0u) << ring.last_io_error();
}

TEST_F(SocketCanVcan, RingSendsWhatThePassLeftBeforeItsWait) {
  SocketCanPort ring;
  ASSERT_TRUE(done(ring.open(kBus, SocketCanPort::kDefaultRcvbufBytes, IoPath::kRing)));
  ASSERT_EQ(ring.io_path(), IoPath::kRing) << ring.io_note();
  const std::vector<CanFrame> requests = assorted_frames();
  const CanFrame answer = make_frame(0x585, 0, 8, "4300100000000000");
  // The peer answers once it has every request: the ring's wait must have
  // sent them itself (nothing else of the ring's runs meanwhile).
  std::vector<TimedCanFrame> heard;
  std::thread peer([&] {
    heard = receive_frames(port_, requests.size());
    port_.send(answer);
  });
  for (const CanFrame& f : requests) ASSERT_TRUE(ring.queue(f));
  ring.flush_at_next_receive();
  EXPECT_EQ(ring.queued(), 0u);
  TimedCanFrame reply[SocketCanPort::kBatch];
  size_t got = 0;
  const uint64_t deadline = monotonic_us() + 30000000u;
  while (got == 0 && monotonic_us() < deadline)
    got = ring.receive_within(reply, SocketCanPort::kBatch, 1000000u);
  peer.join();
  EXPECT_EQ(texts(heard), texts(requests));
  ASSERT_EQ(got, 1u);
  EXPECT_TRUE(same_frame(reply[0].frame, answer));
  EXPECT_EQ(ring.counters().tx_frames, requests.size());
}

TEST(SocketCanTransmit, FullQueueRefusesAndCountsDrops) {
  // A plugged queue of 32 bytes holds two CAN frames (16 bytes each).
  ASSERT_EQ(run_command({"tc", "qdisc", "add", "dev", kSpare, "root", "plug", "limit", "32"}), 0);
  Cleanup unplug{{"tc", "qdisc", "del", "dev", kSpare, "root"}};
  SocketCanPort port;
  ASSERT_TRUE(done(port.open(kSpare)));
  const CanFrame f = make_frame(0x321, 0, 2, "BEEF");
  EXPECT_TRUE(port.send(f));
  EXPECT_TRUE(port.send(f));
  EXPECT_FALSE(port.send(f));
  const CanFrame three[] = {f, f, f};
  EXPECT_EQ(port.send(three, 3), 0u);
  const CanSink sink = port.sink();
  EXPECT_FALSE(sink.send(sink.ctx, f));
  EXPECT_EQ(port.counters().tx_frames, 2u);
  EXPECT_EQ(port.counters().tx_dropped, 5u);
  EXPECT_EQ(port.counters().tx_errors, 0u);
}

TEST(SocketCanTransmit, RingKeepsWhatAFullQueueRefusedInOrder) {
  ASSERT_EQ(run_command({"tc", "qdisc", "add", "dev", kSpare, "root", "plug", "limit", "32"}), 0);
  Cleanup unplug{{"tc", "qdisc", "del", "dev", kSpare, "root"}};
  SocketCanPort port;
  ASSERT_TRUE(done(port.open(kSpare, SocketCanPort::kDefaultRcvbufBytes, IoPath::kRing)));
  ASSERT_EQ(port.io_path(), IoPath::kRing) << port.io_note();
  const CanFrame frames[] = {make_frame(0x321, 0, 1, "01"), make_frame(0x321, 0, 1, "02"),
                             make_frame(0x321, 0, 1, "03"), make_frame(0x321, 0, 1, "04"),
                             make_frame(0x321, 0, 1, "05")};
  for (const CanFrame& f : frames) ASSERT_TRUE(port.queue(f));
  port.flush();
  // The refusals are known once the ring's completions are reaped.
  TimedCanFrame none[1];
  EXPECT_EQ(port.receive(none, 1), 0u);
  // The plug holds two; the third was refused and cancelled the rest: all
  // three are queued again, oldest first, none dropped.
  EXPECT_EQ(port.counters().tx_frames, 2u);
  EXPECT_EQ(port.counters().tx_dropped, 0u);
  EXPECT_EQ(port.counters().tx_errors, 0u);
  ASSERT_EQ(port.queued(), 3u);
  // A send of its own (sendmmsg at once) finds the queue full as well.
  EXPECT_FALSE(port.send(frames[0]));
  EXPECT_EQ(port.counters().tx_dropped, 1u);
}

TEST(SocketCanTransmit, DownInterfaceAndInvalidFramesAreErrors) {
  SocketCanPort port;
  ASSERT_TRUE(done(port.open(kSpare)));
  EXPECT_FALSE(port.send(make_frame(0x800, 0, 0)));  // id needs 12 bits
  CanFrame long_frame = make_frame(0x100, 0, 8);
  long_frame.dlc = 9;
  EXPECT_FALSE(port.send(long_frame));
  EXPECT_EQ(port.counters().tx_errors, 2u);

  ASSERT_EQ(run_command({"ip", "link", "set", "dev", kSpare, "down"}), 0);
  Cleanup up{{"ip", "link", "set", "dev", kSpare, "up"}};
  EXPECT_FALSE(port.send(make_frame(0x100, 0, 0)));
  EXPECT_EQ(port.counters().tx_errors, 3u);
  EXPECT_EQ(port.counters().tx_dropped, 0u);
  EXPECT_NE(strstr(port.last_io_error(), "send"), nullptr) << port.last_io_error();
}

}  // namespace
