// Test helper for the black-box CANopen suites: a harness that drives a
// canopen::Node with a virtual clock, a minimal SDO client that checks every
// response it gets (size, toggles, c bit), and OD snapshots that prove an
// aborted request changed nothing.
#pragma once
#include <gtest/gtest.h>
#include <stdint.h>
#include <string.h>

#include <cstdio>
#include <initializer_list>
#include <string>
#include <vector>

#include "canopen/node.h"
#include "frame_log.h"
#include "ionode/io_node.h"

namespace mb2co {
namespace test {

using Frames = std::vector<std::string>;
using Bytes = std::vector<uint8_t>;

/// Every row's current bytes, in row order; 1013h, the network clock that
/// reads the time of each frame, as empty.
inline std::vector<Bytes> od_snapshot(const canopen::ObjectDictionary& od) {
  std::vector<Bytes> rows;
  const uint16_t clock = od.find(0x1013, 0);
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    if (r == clock) {
      rows.emplace_back();
      continue;
    }
    uint8_t buf[64];
    const uint16_t n = od.copy_out(r, buf, sizeof buf);
    rows.emplace_back(buf, buf + n);
  }
  return rows;
}

/// "<583> 80 LL HH SS c0 c1 c2 c3": the abort frame CiA 301 §7.2.4.3.17 prescribes.
inline std::string abort_frame(uint8_t node_id, uint16_t index, uint8_t sub, uint32_t code) {
  return to_string(F(0x580u + node_id, {0x80, static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8),
                                        sub, static_cast<uint8_t>(code), static_cast<uint8_t>(code >> 8),
                                        static_cast<uint8_t>(code >> 16), static_cast<uint8_t>(code >> 24)}));
}

inline CanFrame frame8(uint32_t id, const uint8_t* b) {
  CanFrame f = {};
  f.id = id;
  f.dlc = 8;
  memcpy(f.data, b, 8);
  return f;
}

/// Drives one Node: frames in at `now`, process(now) after each step.
class Harness {
 public:
  Harness(canopen::Node& node, FrameLog& bus) : node_(node), bus_(bus) {}

  uint32_t now = 0;  ///< virtual microsecond clock (wraps like micros())

  uint8_t id() const { return node_.node_id(); }
  canopen::Node& node() { return node_; }

  /// Hands a frame in, then lets the node process at the same instant.
  void rx(const CanFrame& f) {
    node_.receive(f, now);
    node_.process(now);
  }
  void advance_us(uint32_t us) {
    now += us;
    node_.process(now);
  }
  /// Advances `us` in steps of `step_us`, calling process() at every step.
  void run_us(uint32_t us, uint32_t step_us = 100) {
    while (us >= step_us) {
      advance_us(step_us);
      us -= step_us;
    }
    if (us != 0) advance_us(us);
  }
  Frames take() { return bus_.take(); }
  std::vector<CanFrame> take_frames() {
    std::vector<CanFrame> f = bus_.frames;
    bus_.frames.clear();
    return f;
  }
  void nmt(uint8_t cmd, uint8_t target) { rx(F(0x000, {cmd, target})); }

  // ---- SDO client ------------------------------------------------------------
  /// Sends an 8-byte request; returns the SDO responses it caused (removed from
  /// the log; other frames stay). Every response must be 8 bytes.
  std::vector<CanFrame> sdo_exchange(std::initializer_list<uint8_t> req) {
    uint8_t b[8] = {};
    uint8_t i = 0;
    for (uint8_t x : req) b[i++] = x;
    return sdo_exchange(b);
  }
  std::vector<CanFrame> sdo_exchange(const uint8_t req[8]) {
    const size_t before = bus_.frames.size();
    rx(frame8(0x600u + id(), req));
    std::vector<CanFrame> out;
    std::vector<CanFrame> keep(bus_.frames.begin(), bus_.frames.begin() + static_cast<long>(before));
    for (size_t k = before; k < bus_.frames.size(); ++k) {
      const CanFrame& f = bus_.frames[k];
      if (f.id == 0x580u + id()) {
        EXPECT_EQ(f.dlc, 8) << "SDO responses are 8 bytes: " << to_string(f);
        EXPECT_FALSE(f.rtr());
        out.push_back(f);
      } else {
        keep.push_back(f);
      }
    }
    bus_.frames = keep;
    return out;
  }
  /// Exactly one response expected; returns it (a zero frame if none came).
  CanFrame sdo(std::initializer_list<uint8_t> req) {
    std::vector<CanFrame> r = sdo_exchange(req);
    EXPECT_EQ(r.size(), 1u) << "expected exactly one SDO response";
    return r.empty() ? CanFrame{} : r[0];
  }
  CanFrame sdo(const uint8_t req[8]) {
    std::vector<CanFrame> r = sdo_exchange(req);
    EXPECT_EQ(r.size(), 1u) << "expected exactly one SDO response";
    return r.empty() ? CanFrame{} : r[0];
  }

  /// Checks that `r` is an abort or the expected confirmation; returns the
  /// abort code (0 if `r` is the confirmation `ok_cmd` for index/sub).
  uint32_t check_response(const CanFrame& r, uint8_t ok_cmd, uint16_t index, uint8_t sub,
                          bool check_mux = true) {
    if (r.data[0] == 0x80) {
      EXPECT_EQ(canopen::le16(&r.data[1]), index) << to_string(r);
      EXPECT_EQ(r.data[3], sub) << to_string(r);
      const uint32_t code = canopen::le32(&r.data[4]);
      EXPECT_NE(code, 0u) << "abort with code 0";
      return code;
    }
    EXPECT_EQ(r.data[0], ok_cmd) << to_string(r);
    if (check_mux) {
      EXPECT_EQ(canopen::le16(&r.data[1]), index) << to_string(r);
      EXPECT_EQ(r.data[3], sub) << to_string(r);
    }
    return 0;
  }

  /// Expedited download of 1..4 bytes with size indicated. 0 or abort code.
  uint32_t download_expedited(uint16_t index, uint8_t sub, const Bytes& data) {
    uint8_t req[8] = {static_cast<uint8_t>(0x23 | ((4 - data.size()) << 2)), static_cast<uint8_t>(index),
                      static_cast<uint8_t>(index >> 8), sub};
    memcpy(&req[4], data.data(), data.size());
    return check_response(sdo(req), 0x60, index, sub);
  }
  /// Segmented download, with or without size indication. 0 or abort code.
  uint32_t download_segmented(uint16_t index, uint8_t sub, const Bytes& data, bool indicate) {
    uint8_t req[8] = {static_cast<uint8_t>(indicate ? 0x21 : 0x20), static_cast<uint8_t>(index),
                      static_cast<uint8_t>(index >> 8), sub};
    if (indicate) canopen::put_le32(&req[4], static_cast<uint32_t>(data.size()));
    uint32_t code = check_response(sdo(req), 0x60, index, sub);
    if (code != 0) return code;
    uint8_t toggle = 0;
    size_t at = 0;
    do {
      const size_t n = data.size() - at < 7 ? data.size() - at : 7;
      const bool last = at + n == data.size();
      uint8_t seg[8] = {static_cast<uint8_t>(toggle | ((7 - n) << 1) | (last ? 1 : 0))};
      memcpy(&seg[1], data.data() + at, n);
      const CanFrame r = sdo(seg);
      if (r.data[0] == 0x80) return check_response(r, 0, index, sub);
      EXPECT_EQ(r.data[0], 0x20 | toggle) << "segment ack " << to_string(r);
      at += n;
      toggle ^= 0x10;
      if (last) break;
    } while (true);
    return 0;
  }
  /// Download as a client would choose: expedited up to 4 bytes.
  uint32_t download(uint16_t index, uint8_t sub, const Bytes& data) {
    return data.size() >= 1 && data.size() <= 4 ? download_expedited(index, sub, data)
                                                : download_segmented(index, sub, data, true);
  }
  uint32_t write(uint16_t index, uint8_t sub, uint32_t value, uint8_t len) {
    Bytes b;
    for (uint8_t i = 0; i < len; ++i) b.push_back(static_cast<uint8_t>(value >> (8 * i)));
    return download_expedited(index, sub, b);
  }
  uint32_t write_u8(uint16_t i, uint8_t s, uint32_t v) { return write(i, s, v, 1); }
  uint32_t write_u16(uint16_t i, uint8_t s, uint32_t v) { return write(i, s, v, 2); }
  uint32_t write_u32(uint16_t i, uint8_t s, uint32_t v) { return write(i, s, v, 4); }
  /// Maps `entries` into the PDO of communication record `comm` (1400h.. an
  /// RPDO, 1800h.. a TPDO) by the CiA 301 procedure (disable, sub 0 = 0,
  /// entries, count) and makes it valid at 200h/180h + node id.
  void map_pdo(uint16_t comm, std::initializer_list<uint32_t> entries) {
    const uint16_t mapping = static_cast<uint16_t>(comm + 0x200);
    const uint32_t cob = (comm >= 0x1800 ? 0x180u : 0x200u) + id();
    ASSERT_EQ(write_u32(comm, 1, 0x80000000u | cob), 0u);
    ASSERT_EQ(write_u8(mapping, 0, 0), 0u);
    uint8_t s = 1;
    for (uint32_t e : entries) ASSERT_EQ(write_u32(mapping, s++, e), 0u) << std::hex << e;
    ASSERT_EQ(write_u8(mapping, 0, static_cast<uint8_t>(entries.size())), 0u);
    ASSERT_EQ(write_u32(comm, 1, cob), 0u);
  }

  /// Upload, expedited or segmented (checking toggles, sizes and the c bit).
  uint32_t upload(uint16_t index, uint8_t sub, Bytes* out) {
    out->clear();
    const CanFrame r = sdo({0x40, static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8), sub});
    if (r.data[0] == 0x80) return check_response(r, 0, index, sub);
    EXPECT_EQ(canopen::le16(&r.data[1]), index);
    EXPECT_EQ(r.data[3], sub);
    const uint8_t cmd = r.data[0];
    EXPECT_EQ(cmd & 0xE0, 0x40) << to_string(r);
    if (cmd & 0x02) {  // expedited
      const uint8_t n = (cmd & 0x01) ? static_cast<uint8_t>(4 - ((cmd >> 2) & 3)) : 4;
      out->assign(&r.data[4], &r.data[4] + n);
      return 0;
    }
    EXPECT_EQ(cmd, 0x41) << "segmented upload indicates its size";
    const uint32_t size = canopen::le32(&r.data[4]);
    uint8_t toggle = 0;
    for (int guard = 0; guard < 64; ++guard) {
      const CanFrame s = sdo({static_cast<uint8_t>(0x60 | toggle)});
      if (s.data[0] == 0x80) return check_response(s, 0, index, sub);
      EXPECT_EQ(s.data[0] & 0xE0, 0x00) << to_string(s);
      EXPECT_EQ(s.data[0] & 0x10, toggle) << "toggle " << to_string(s);
      const uint8_t n = static_cast<uint8_t>(7 - ((s.data[0] >> 1) & 7));
      out->insert(out->end(), &s.data[1], &s.data[1] + n);
      toggle ^= 0x10;
      if (s.data[0] & 0x01) break;
      EXPECT_EQ(n, 7) << "only the last segment may be short";
    }
    EXPECT_EQ(out->size(), size) << "bytes received vs size indicated";
    return 0;
  }
  /// Numeric read that must succeed.
  uint32_t read(uint16_t index, uint8_t sub) {
    Bytes b;
    const uint32_t code = upload(index, sub, &b);
    EXPECT_EQ(code, 0u) << std::hex << "read " << index << "sub" << int(sub);
    uint32_t v = 0;
    for (size_t i = 0; i < b.size() && i < 4; ++i) v |= static_cast<uint32_t>(b[i]) << (8 * i);
    return v;
  }
  std::string read_string(uint16_t index, uint8_t sub) {
    Bytes b;
    EXPECT_EQ(upload(index, sub, &b), 0u);
    return std::string(b.begin(), b.end());
  }

  /// Sends `req`, expects exactly the abort frame and an unchanged OD.
  void expect_abort(std::initializer_list<uint8_t> req, uint16_t index, uint8_t sub, uint32_t code) {
    const std::vector<Bytes> before = od_snapshot(node_.od());
    const std::vector<CanFrame> r = sdo_exchange(req);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(to_string(r[0]), abort_frame(id(), index, sub, code));
    EXPECT_TRUE(od_snapshot(node_.od()) == before) << "an aborted request changed the OD";
  }

 private:
  canopen::Node& node_;
  FrameLog& bus_;
};

inline Bytes bytes_of(const std::string& s) {
  return Bytes(s.begin(), s.end());
}

/// The CiA 401 I/O node with node id 3, started and pre-operational, log empty.
class IoNodeTest : public ::testing::Test {
 protected:
  static constexpr uint8_t kId = 3;
  void SetUp() override {
    io.start(kId, h.now);
    bus.frames.clear();
  }
  void operational() {
    h.nmt(0x01, kId);
    bus.frames.clear();
  }
  canopen::ObjectDictionary& od() { return io.od(); }
  /// Current value of (index, sub) read locally (no SDO).
  uint32_t value(uint16_t index, uint8_t sub) {
    const uint16_t row = io.od().find(index, sub);
    EXPECT_NE(row, uint16_t{canopen::ObjectDictionary::kNoRow});
    return io.od().get(row);
  }

  /// Current text of a string entry read locally (no SDO).
  std::string text(uint16_t index, uint8_t sub) {
    char buf[64];
    const uint16_t n =
        io.od().copy_out(io.od().find(index, sub), reinterpret_cast<uint8_t*>(buf), sizeof buf);
    return std::string(buf, n);
  }

  FrameLog bus;
  ionode::IoNode io{bus.sink()};
  Harness h{io.node(), bus};
};

}  // namespace test
}  // namespace mb2co
