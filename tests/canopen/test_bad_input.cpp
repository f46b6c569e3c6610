// Bad input, systematically: every DLC 0..8, data and RTR, on every COB-ID the
// node listens or talks on, in every NMT state; every SDO command byte in
// every server state. Each gets what CiA 301 prescribes (abort, EMCY or
// silence) and the node stays consistent afterwards.
#include <gtest/gtest.h>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

class BadInput : public IoNodeTest {
 protected:
  /// Brings the node into `state` with a clean log and no active errors.
  void enter(NmtState state) {
    h.nmt(0x81, kId);  // reset node: fresh services and OD
    if (state == kNmtOperational) h.nmt(0x01, kId);
    if (state == kNmtStopped) h.nmt(0x02, kId);
    bus.frames.clear();
  }
  /// A valid request still gets the right answer.
  void expect_alive() {
    if (io.node().nmt_state() == kNmtStopped) h.nmt(0x80, kId);
    EXPECT_EQ(to_string(h.sdo({0x40, 0x18, 0x10, 0x02})), "<583> 42 18 10 02 01 04 00 00");
    EXPECT_EQ(h.read_string(0x1008, 0), "mb2co I/O node");
  }
};

CanFrame make(uint32_t id, uint8_t dlc, bool rtr, uint8_t seed) {
  CanFrame f = {};
  f.id = id;
  f.dlc = dlc;
  f.flags = rtr ? CanFrame::kRtr : 0;
  for (uint8_t i = 0; i < 8; ++i) f.data[i] = static_cast<uint8_t>(seed * 37 + i * 11 + 1);
  return f;
}

TEST_F(BadInput, EveryLengthOnEveryIdInEveryState) {
  // Ids the node transmits on, or that belong to nobody here: never answered.
  const uint32_t silent_ids[] = {0x083, 0x583, 0x283, 0x383, 0x483, 0x303, 0x403,
                                 0x503, 0x604, 0x602, 0x704, 0x7FF, 0x001, 0x100};
  for (NmtState state : {kNmtPreOperational, kNmtOperational, kNmtStopped}) {
    for (uint8_t dlc = 0; dlc <= 8; ++dlc) {
      for (bool rtr : {false, true}) {
        SCOPED_TRACE(testing::Message() << "state " << int(state) << " dlc " << int(dlc) << " rtr " << rtr);
        const bool op = state == kNmtOperational;
        const bool stopped = state == kNmtStopped;
        for (uint32_t id : silent_ids) {
          enter(state);
          const std::vector<Bytes> before = od_snapshot(od());
          h.rx(make(id, dlc, rtr, dlc));
          EXPECT_EQ(h.take(), Frames({})) << std::hex << id;
          EXPECT_TRUE(od_snapshot(od()) == before);
        }
        // SDO request id: only 8-byte data frames are requests.
        if (dlc != 8 || rtr) {
          enter(state);
          const std::vector<Bytes> before = od_snapshot(od());
          CanFrame f = make(0x603, dlc, rtr, 0);
          f.data[0] = 0x2B;  // would be a write of 2101h
          f.data[1] = 0x01;
          f.data[2] = 0x21;
          f.data[3] = 0x00;
          h.rx(f);
          EXPECT_EQ(h.take(), Frames({}));
          EXPECT_TRUE(od_snapshot(od()) == before);
        }
        // NMT: only 2-byte data frames are commands.
        if (dlc != 2 || rtr) {
          enter(state);
          h.rx(make(0x000, dlc, rtr, 0) /* byte 0 = 01h: start */);
          EXPECT_EQ(io.node().nmt_state(), state);
          EXPECT_EQ(h.take(), Frames({}));
        }
        // SYNC (1019h = 0): a data-less data frame; other lengths -> EMCY 8240h
        // while SYNC is consumed (pre-operational, operational); RTR ignored.
        {
          enter(state);
          h.rx(make(0x080, dlc, rtr, 0));
          Frames want;
          if (!rtr && dlc != 0 && !stopped) want.push_back("<083> 40 82 11 00 00 00 00 00");
          // (A good SYNC has no visible effect: TPDO1 is event-driven.)
          EXPECT_EQ(h.take(), want);
        }
        // Error control id: RTR is a guarding request, data frames are nothing.
        {
          enter(state);
          h.rx(make(0x703, dlc, rtr, 0));
          Frames want;
          if (rtr) want.push_back(stopped ? "<703> 04" : op ? "<703> 05" : "<703> 7F");
          EXPECT_EQ(h.take(), want);
        }
        // Own TPDO1: RTR answered in operational; data frames ignored.
        {
          enter(state);
          h.rx(make(0x183, dlc, rtr, 0));
          Frames want;
          if (rtr && op) want.push_back("<183> 00 00");
          EXPECT_EQ(h.take(), want);
        }
        // RPDO1 (2 bytes mapped): short -> 8210h, dropped; long -> 8220h,
        // applied; RTR ignored; only in operational.
        {
          enter(state);
          CanFrame f = make(0x203, dlc, rtr, 0);
          f.data[0] = 0xA5;
          f.data[1] = 0x5A;
          h.rx(f);
          Frames want;
          const bool taken = op && !rtr;
          if (taken && dlc < 2) want.push_back("<083> 10 82 11 00 00 00 00 00");
          if (taken && dlc > 2) want.push_back("<083> 20 82 11 00 00 00 00 00");
          EXPECT_EQ(h.take(), want);
          EXPECT_EQ(io.output(0), taken && dlc >= 2 ? 0xA5 : 0x00);
          EXPECT_EQ(io.output(1), taken && dlc >= 2 ? 0x5A : 0x00);
        }
        // Extended frames are never CANopen (CiA 301 uses 11-bit ids here).
        for (uint32_t id : {0x000u, 0x080u, 0x183u, 0x203u, 0x603u, 0x703u}) {
          enter(state);
          CanFrame f = make(id, dlc, rtr, 0);
          f.flags = static_cast<uint8_t>(f.flags | CanFrame::kExtended);
          f.data[0] = 0x81;
          f.data[1] = 0x00;
          h.rx(f);
          EXPECT_EQ(h.take(), Frames({})) << std::hex << id;
          EXPECT_EQ(io.node().nmt_state(), state);
        }
      }
    }
  }
  expect_alive();
}

/// Expected first byte of the response to `b0` sent with multiplexer 2101h
/// sub 0 and data 05 00 00 00 while the server is idle, or 0x80 + code.
struct Expect {
  bool silent;
  uint8_t cmd;
  uint32_t abort;
};

Expect idle_oracle(uint8_t b0) {
  const uint8_t ccs = b0 >> 5;
  switch (ccs) {
    case 1: {
      const bool e = b0 & 0x02;
      const bool s = b0 & 0x01;
      if (e) {
        const unsigned len = s ? 4u - ((b0 >> 2) & 3u) : 2u;
        if (len < 2) return {false, 0x80, kAbortTooShort};
        if (len > 2) return {false, 0x80, kAbortTooLong};
        return {false, 0x60, 0};
      }
      if (s) return {false, 0x80, kAbortTooLong};  // announces 5 bytes for a U16
      return {false, 0x60, 0};                     // segmented, size unknown: started
    }
    case 2:
      return {false, 0x4B, 0};
    case 4:
      return {true, 0, 0};
    default:  // 0, 3 (segments without a transfer), 5, 6, 7
      return {false, 0x80, kAbortCommand};
  }
}

TEST_F(BadInput, EveryCommandByteWhileIdle) {
  for (unsigned b = 0; b < 256; ++b) {
    const uint8_t b0 = static_cast<uint8_t>(b);
    SCOPED_TRACE(testing::Message() << "byte 0 = " << std::hex << b);
    const Expect want = idle_oracle(b0);
    ASSERT_EQ(h.write_u16(0x2101, 0, 10), 0u);
    const std::vector<CanFrame> r = h.sdo_exchange({b0, 0x01, 0x21, 0x00, 0x05, 0x00, 0x00, 0x00});
    if (want.silent) {
      EXPECT_TRUE(r.empty());
      continue;
    }
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].data[0], want.cmd);
    if (want.cmd == 0x80) {
      // Segments without a transfer carry the last multiplexer (2101h here).
      EXPECT_EQ(to_string(r[0]), abort_frame(kId, 0x2101, 0, want.abort));
      EXPECT_EQ(value(0x2101, 0), 10u) << "unchanged after an abort";
    } else if (want.cmd == 0x60 && (b0 & 0x02)) {
      EXPECT_EQ(value(0x2101, 0), 5u);
    } else if (want.cmd == 0x4B) {
      EXPECT_EQ(to_string(r[0]), "<583> 4B 01 21 00 0A 00 00 00");
    }
    // Whatever was started ends here.
    EXPECT_TRUE(h.sdo_exchange({0x80, 0x01, 0x21, 0x00, 0, 0, 0, 0}).empty());
  }
  expect_alive();
}

TEST_F(BadInput, EveryCommandByteDuringASegmentedDownload) {
  for (unsigned b = 0; b < 256; ++b) {
    const uint8_t b0 = static_cast<uint8_t>(b);
    SCOPED_TRACE(testing::Message() << "byte 0 = " << std::hex << b);
    ASSERT_EQ(h.download(0x2000, 0, bytes_of("old")), 0u);
    ASSERT_EQ(h.check_response(h.sdo({0x20, 0x00, 0x20, 0x00}), 0x60, 0x2000, 0), 0u);
    const std::vector<CanFrame> r = h.sdo_exchange({b0, 'n', 'e', 'w', '!', '!', '!', '!'});
    const uint8_t ccs = b0 >> 5;
    if (ccs == 4) {
      EXPECT_TRUE(r.empty());
      EXPECT_EQ(text(0x2000, 0), "old");
      continue;
    }
    ASSERT_EQ(r.size(), 1u);
    if (ccs == 0) {
      if (b0 & 0x10) {
        EXPECT_EQ(to_string(r[0]), abort_frame(kId, 0x2000, 0, kAbortToggle));
        EXPECT_EQ(text(0x2000, 0), "old");
      } else {
        EXPECT_EQ(to_string(r[0]), "<583> 20 00 00 00 00 00 00 00");
        const size_t n = 7u - ((b0 >> 1) & 7u);
        if (b0 & 0x01) {
          EXPECT_EQ(text(0x2000, 0), std::string("new!!!!", n)) << "last segment stores";
        } else {
          EXPECT_EQ(text(0x2000, 0), "old");
        }
      }
    } else if (ccs == 1 || ccs == 2) {
      // A new initiate (multiplexer 656Eh sub 77h does not exist) replaces it.
      EXPECT_EQ(to_string(r[0]), abort_frame(kId, 0x656E, 0x77, kAbortNoObject));
      EXPECT_EQ(text(0x2000, 0), "old");
    } else {
      const uint16_t idx = ccs == 3 ? 0x2000 : 0x656E;
      const uint8_t sub = ccs == 3 ? 0x00 : 0x77;
      EXPECT_EQ(to_string(r[0]), abort_frame(kId, idx, sub, kAbortCommand));
      EXPECT_EQ(text(0x2000, 0), "old");
    }
    EXPECT_TRUE(h.sdo_exchange({0x80, 0x00, 0x20, 0x00, 0, 0, 0, 0}).empty());
  }
  expect_alive();
}

TEST_F(BadInput, EveryCommandByteDuringASegmentedUpload) {
  for (unsigned b = 0; b < 256; ++b) {
    const uint8_t b0 = static_cast<uint8_t>(b);
    SCOPED_TRACE(testing::Message() << "byte 0 = " << std::hex << b);
    ASSERT_EQ(to_string(h.sdo({0x40, 0x08, 0x10, 0x00})), "<583> 41 08 10 00 0E 00 00 00");
    const std::vector<CanFrame> r = h.sdo_exchange({b0, 0x08, 0x10, 0x00, 0, 0, 0, 0});
    const uint8_t ccs = b0 >> 5;
    if (ccs == 4) {
      EXPECT_TRUE(r.empty());
      continue;
    }
    ASSERT_EQ(r.size(), 1u);
    if (ccs == 3) {
      EXPECT_EQ(to_string(r[0]), (b0 & 0x10) ? abort_frame(kId, 0x1008, 0, kAbortToggle)
                                             : std::string("<583> 00 6D 62 32 63 6F 20 49"));
    } else if (ccs == 2) {
      EXPECT_EQ(to_string(r[0]), "<583> 41 08 10 00 0E 00 00 00");  // starts over
    } else if (ccs == 1) {
      EXPECT_EQ(r[0].data[0], 0x80);
      EXPECT_EQ(le32(&r[0].data[4]), kAbortReadOnly);
    } else {
      EXPECT_EQ(to_string(r[0]), abort_frame(kId, 0x1008, 0, kAbortCommand));
    }
    EXPECT_TRUE(h.sdo_exchange({0x80, 0x08, 0x10, 0x00, 0, 0, 0, 0}).empty());
  }
  expect_alive();
}

TEST_F(BadInput, SegmentsAfterTheLastOneAreOutOfSequence) {
  ASSERT_EQ(h.download_segmented(0x2000, 0, bytes_of("0123456789"), true), 0u);
  h.expect_abort({0x10, 'x', 'x', 'x', 'x', 'x', 'x', 'x'}, 0x2000, 0, kAbortCommand);
  h.expect_abort({0x00, 'x', 'x', 'x', 'x', 'x', 'x', 'x'}, 0x2000, 0, kAbortCommand);
  EXPECT_EQ(text(0x2000, 0), "0123456789");
}

}  // namespace
}  // namespace test
}  // namespace mb2co
