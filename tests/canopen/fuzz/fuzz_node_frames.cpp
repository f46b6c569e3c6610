// libFuzzer target: the input is a sequence of records, each one frame and
// the time that passes before it, handed to an I/O node (node id 3):
//   byte 0: bits 0..3 DLC (values above 8 are taken modulo 9), bit 4 RTR,
//           bit 5 extended, bits 6..7 time scale (µs, ×100, ×10000, ×1000000)
//   byte 1: time step (× the scale)
//   byte 2: id: < 0xF0 picks one of the node's COB-IDs, else the 11-bit id is
//           (byte 2 & 7) << 8 | byte 3 (and byte 3 is consumed)
//   then DLC data bytes (fewer if the input ends).
// Invariants (violations abort): every frame sent passes frame_violation();
// afterwards the const entries are unchanged (a $NODEID-relative one less
// the node id: frames may give the node another id, 2001h/1 + a reset) and
// the node, put into pre-operational, answers a valid SDO upload correctly
// under the id it has then.
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <string>
#include <vector>

#include "fuzz/node_invariants.h"
#include "fuzz_support.h"
#include "ionode/io_node.h"

namespace {

using namespace mb2co;

struct Bus {
  ionode::IoNode* node = nullptr;
  std::vector<CanFrame> sdo;  ///< SDO responses since the last clear
  static bool send(void* ctx, const CanFrame& f) {
    Bus& b = *static_cast<Bus*>(ctx);
    const std::string why = test::frame_violation(*b.node, f);
    if (!why.empty()) {
      fprintf(stderr, "invariant violated: %s (id %03X dlc %u)\n", why.c_str(), static_cast<unsigned>(f.id),
              f.dlc);
      abort();
    }
    if (f.id == 0x580u + b.node->od().node_id()) b.sdo.push_back(f);
    return true;
  }
};

const uint32_t kIds[] = {0x000, 0x080, 0x603, 0x703, 0x183, 0x283, 0x383, 0x483,
                         0x203, 0x303, 0x403, 0x503, 0x705, 0x583, 0x083, 0x090};
const uint32_t kScale[] = {1, 100, 10000, 1000000};

using fuzz::require;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bus bus;
  ionode::IoNode io(CanSink{&Bus::send, &bus});
  bus.node = &io;
  uint32_t now = 0xFFFFFFFFu - 5000000u;  // 5 s before the wrap
  io.start(3, now);

  canopen::ObjectDictionary& od = io.od();
  const std::vector<uint8_t> consts = fuzz::const_values(od);

  size_t at = 0;
  while (at + 3 <= size) {
    const uint8_t ctl = data[at];
    const uint32_t dt = data[at + 1] * kScale[ctl >> 6];
    const uint8_t sel = data[at + 2];
    at += 3;
    CanFrame f = {};
    if (sel < 0xF0) {
      f.id = kIds[sel % (sizeof kIds / sizeof kIds[0])];
    } else {
      if (at >= size) break;
      f.id = (static_cast<uint32_t>(sel & 7) << 8) | data[at++];
    }
    f.dlc = static_cast<uint8_t>((ctl & 0x0F) % 9);
    f.flags =
        static_cast<uint8_t>(((ctl & 0x10) ? CanFrame::kRtr : 0) | ((ctl & 0x20) ? CanFrame::kExtended : 0));
    for (uint8_t i = 0; i < f.dlc && at < size; ++i) f.data[i] = data[at++];
    now += dt;
    io.process(now);
    io.receive(f, now);
    io.process(now);
  }

  require(fuzz::const_values(od) == consts, "a const entry changed");
  // Pre-operational, then a valid upload of 1018h sub 2 must be answered.
  const uint8_t id = od.node_id();
  CanFrame nmt = {};
  nmt.id = 0;
  nmt.dlc = 2;
  nmt.data[0] = 0x80;
  nmt.data[1] = id;
  io.receive(nmt, now);
  io.process(now);
  bus.sdo.clear();
  CanFrame req = {};
  req.id = 0x600u + id;
  req.dlc = 8;
  req.data[0] = 0x40;
  req.data[1] = 0x18;
  req.data[2] = 0x10;
  req.data[3] = 0x02;
  io.receive(req, now);
  io.process(now);
  const uint8_t want[8] = {0x42, 0x18, 0x10, 0x02, 0x01, 0x04, 0x00, 0x00};
  require(bus.sdo.size() == 1 && memcmp(bus.sdo[0].data, want, 8) == 0,
          "the node no longer answers a valid SDO upload");
  return 0;
}
