// Fixed-count driver for `valgrind --tool=callgrind`: each operation of the
// benchmarks runs exactly kRuns times inside its own function, so
// callgrind.sh can report instructions per operation (repeatable, unlike
// wall-clock time). Not a test; see docs/performance.md.
#include <cstdio>

#include "canopen/od_comm.h"
#include "ionode/io_node.h"

namespace {

using namespace mb2co;
const int kRuns = 10000;
uint32_t g_frames = 0;
bool count(void*, const CanFrame&) {
  ++g_frames;
  return true;
}

CanFrame frame(uint32_t id, uint8_t dlc, const uint8_t* bytes) {
  CanFrame f = {};
  f.id = id;
  f.dlc = dlc;
  for (uint8_t i = 0; i < dlc; ++i) f.data[i] = bytes[i];
  return f;
}

__attribute__((noinline)) uint32_t run_od_lookup(canopen::ObjectDictionary& od) {
  uint32_t sum = 0;
  for (int i = 0; i < kRuns; ++i) sum += od.find(static_cast<uint16_t>(i & 1 ? 0x1A00 : 0x6000), 1);
  return sum;
}

__attribute__((noinline)) void run_sdo_upload(ionode::IoNode& node) {
  const uint8_t req[8] = {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0};
  const CanFrame f = frame(0x603, 8, req);
  for (int i = 0; i < kRuns; ++i) node.receive(f, 1000);
}

__attribute__((noinline)) void run_sync_4_tpdos(ionode::IoNode& node) {
  const CanFrame sync = frame(0x080, 0, nullptr);
  for (int i = 0; i < kRuns; ++i) node.receive(sync, 2000);
}

void make_sync_tpdo(canopen::ObjectDictionary& od, uint8_t n) {
  uint8_t b[4];
  const uint16_t comm = static_cast<uint16_t>(0x1800 + n);
  const uint16_t map = static_cast<uint16_t>(0x1A00 + n);
  canopen::put_le32(b, 0x80000000u | (0x180u + 0x100u * n + 3));
  od.write(comm, 1, b, 4);
  b[0] = 0;
  od.write(map, 0, b, 1);
  canopen::put_le32(b, MB2CO_PDO_MAP_ENTRY(0x6000, 1, 8));
  od.write(map, 1, b, 4);
  canopen::put_le32(b, MB2CO_PDO_MAP_ENTRY(0x6000, 2, 8));
  od.write(map, 2, b, 4);
  canopen::put_le32(b, MB2CO_PDO_MAP_ENTRY(0x1001, 0, 8));
  od.write(map, 3, b, 4);
  b[0] = 3;
  od.write(map, 0, b, 1);
  b[0] = 1;
  od.write(comm, 2, b, 1);
  canopen::put_le32(b, 0x180u + 0x100u * n + 3);
  od.write(comm, 1, b, 4);
}

}  // namespace

int main() {
  static ionode::IoNode node(CanSink{&count, nullptr});
  node.start(3, 0);
  const uint32_t sum = run_od_lookup(node.od());
  run_sdo_upload(node);
  for (uint8_t n = 0; n < 4; ++n) make_sync_tpdo(node.od(), n);
  const uint8_t start[2] = {0x01, 0x03};
  node.receive(frame(0x000, 2, start), 0);
  g_frames = 0;
  run_sync_4_tpdos(node);
  std::printf("runs %d, lookup checksum %u, TPDOs sent %u\n", kRuns, sum, g_frames);
  return g_frames == 4u * kRuns ? 0 : 1;
}
