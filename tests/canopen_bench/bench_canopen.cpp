// Google Benchmarks of the CANopen core's hot paths (figures in
// docs/performance.md): OD lookup, expedited SDO request → response, and a
// SYNC that makes 4 synchronous TPDOs.
#include <benchmark/benchmark.h>

#include <array>

#include "bench_support.h"
#include "canopen/od_comm.h"
#include "ionode/io_node.h"

namespace mb2co {
namespace {

using bench::frame;

struct CountingSink {
  uint32_t frames = 0;
  uint8_t last = 0;
  static bool send(void* ctx, const CanFrame& f) {
    CountingSink& s = *static_cast<CountingSink*>(ctx);
    ++s.frames;
    s.last = f.data[0];
    return true;
  }
  CanSink sink() { return CanSink{&CountingSink::send, this}; }
};

void BM_OdLookup(benchmark::State& state) {
  CountingSink bus;
  ionode::IoNode node(bus.sink());
  const uint16_t keys[][2] = {{0x1000, 0}, {0x1017, 0}, {0x1400, 1}, {0x1A00, 2},
                              {0x1803, 5}, {0x6000, 1}, {0x6200, 2}, {0x0007, 0}};
  size_t i = 0;
  for (auto _ : state) {
    const uint16_t* k = keys[i++ % 8];
    benchmark::DoNotOptimize(node.od().find(k[0], static_cast<uint8_t>(k[1])));
  }
  state.counters["rows"] = node.od().row_count();
}
BENCHMARK(BM_OdLookup);

// One expedited SDO request handed in, its response built and sent;
// `reply` is the command byte the response must carry.
void sdo_request(benchmark::State& state, std::array<uint8_t, 8> req, uint8_t reply) {
  CountingSink bus;
  ionode::IoNode node(bus.sink());
  node.start(3, 0);
  const CanFrame f = frame(0x603, 8, req.data());
  for (auto _ : state) node.receive(f, 1000);
  if (bus.last != reply) state.SkipWithError("unexpected SDO response");
}
// Upload of 1000h (device type); download of 1017h = 500.
BENCHMARK_CAPTURE(sdo_request, ExpeditedUpload, {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0}, 0x42);
BENCHMARK_CAPTURE(sdo_request, ExpeditedDownload, {0x2B, 0x17, 0x10, 0x00, 0xF4, 0x01, 0, 0}, 0x60);

void BM_Sync4Tpdos(benchmark::State& state) {
  CountingSink bus;
  ionode::IoNode node(bus.sink());
  node.start(3, 0);
  for (uint8_t n = 0; n < 4; ++n) bench::make_sync_tpdo(node.od(), n);
  const uint8_t start[2] = {0x01, 0x03};
  node.receive(frame(0x000, 2, start), 0);
  const CanFrame sync = frame(0x080, 0, nullptr);
  bus.frames = 0;
  for (auto _ : state) node.receive(sync, 2000);
  if (bus.frames != 4 * state.iterations()) state.SkipWithError("SYNC did not make 4 TPDOs");
}
BENCHMARK(BM_Sync4Tpdos);

}  // namespace
}  // namespace mb2co
