// Cost of one control cycle of mb2co-plant without the serial wait: decode
// the registers, controller + plant step, encode the RUN command, and the
// per-cycle log row. Steady running on the default plant (20 ms step).
#include <benchmark/benchmark.h>

#include "cycle_log.h"
#include "fake_gateway.h"
#include "gateway/line_app.h"
#include "latency_cycle.h"
#include "station_cycle.h"

using namespace mb2co;
using namespace mb2co::pcapp;

namespace {
plant::PlantConfig app_config() {
  plant::PlantConfig c;
  c.step_ms = 20;  // the app's default cycle
  return c;
}

void started(FakeGateway& gw, StationCycle& station) {
  station.step(gw.in, gw.out);
  gw.set(Field::kInputs, gateway::kStart);
  station.step(gw.in, gw.out);
  gw.set(Field::kInputs, 0);
  gw.set(Field::kRunState, 1);
  gw.set(Field::kPrevStatus, gateway::kNeighbourAlive);
  gw.set(Field::kNextStatus, gateway::kNeighbourAlive);
}

void BM_StationCycle(benchmark::State& state) {
  FakeGateway gw;
  StationCycle station(gw.layout, app_config());
  started(gw, station);
  for (auto _ : state) {
    station.step(gw.in, gw.out);
    benchmark::DoNotOptimize(gw.out.regs[0][0]);
  }
  if (!station.controller().running()) state.SkipWithError("station stopped");
}
BENCHMARK(BM_StationCycle);

void BM_StationCycleWithLog(benchmark::State& state) {
  FakeGateway gw;
  StationCycle station(gw.layout, app_config());
  started(gw, station);
  std::vector<const char*> names = {"cycle", "t_us", "link", "modbus_us"};
  for (const char* n : station.column_names()) names.push_back(n);
  std::vector<LogValue> row;
  std::string line;
  int64_t cycle = 0;
  for (auto _ : state) {
    station.step(gw.in, gw.out);
    const std::string e = station.take_event();
    row.clear();
    row.push_back({++cycle, nullptr});
    row.push_back({cycle * 20000, nullptr});
    row.push_back({1, nullptr});
    row.push_back({4500, nullptr});
    station.columns(row);
    line.clear();
    format_row(LogFormat::kCsv, names, row, line);
    benchmark::DoNotOptimize(line.data());
    benchmark::DoNotOptimize(e.data());
  }
}
BENCHMARK(BM_StationCycleWithLog);

void BM_StatusLine(benchmark::State& state) {
  FakeGateway gw;
  StationCycle station(gw.layout, app_config());
  started(gw, station);
  for (auto _ : state) {
    std::string s = station.status();
    benchmark::DoNotOptimize(s.data());
  }
}
BENCHMARK(BM_StatusLine);

void BM_LatencyCycle(benchmark::State& state) {
  FakeGateway gw;
  LatencyCycle lab(gw.layout, false, gateway::kStart, 0);
  uint32_t t = 0;
  for (auto _ : state) {
    gw.set(Field::kInputs, (t / 1000) & 1 ? gateway::kStart : 0);
    gw.set(Field::kLedUs, t);
    ++t;
    lab.step(gw.in, gw.out);
    benchmark::DoNotOptimize(gw.out.regs[0][1]);
  }
}
BENCHMARK(BM_LatencyCycle);
}  // namespace
