// Fixed-count driver for `valgrind --tool=callgrind`: each operation of the
// benchmarks runs exactly kRuns times inside its own function, so
// callgrind.sh can report instructions per operation (repeatable, unlike
// wall-clock time). Not a test; see docs/performance.md.
#include <cstdio>

#include "bench_support.h"
#include "canopen/od_comm.h"
#include "ionode/io_node.h"

namespace {

using namespace mb2co;
using bench::frame;
const int kRuns = 10000;
uint32_t g_frames = 0;
bool count(void*, const CanFrame&) {
  ++g_frames;
  return true;
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

}  // namespace

int main() {
  static ionode::IoNode node(CanSink{&count, nullptr});
  node.start(3, 0);
  const uint32_t sum = run_od_lookup(node.od());
  run_sdo_upload(node);
  for (uint8_t n = 0; n < 4; ++n) bench::make_sync_tpdo(node.od(), n);
  const uint8_t start[2] = {0x01, 0x03};
  node.receive(frame(0x000, 2, start), 0);
  g_frames = 0;
  run_sync_4_tpdos(node);
  std::printf("runs %d, lookup checksum %u, TPDOs sent %u\n", kRuns, sum, g_frames);
  return g_frames == 4u * kRuns ? 0 : 1;
}
