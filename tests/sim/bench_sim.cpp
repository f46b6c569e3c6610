// Speed of the line simulator: 4 stations at 500 kbit/s, PCs running the
// plant and controller with a 20 ms cycle, Arduinos with the ATmega328P pass
// times. Reports simulated seconds per CPU second (x_real_time).
#include <benchmark/benchmark.h>

#include "gateway/line_app.h"
#include "sim/line.h"
#include "sim/pc_programs.h"

namespace {

using namespace mb2co;
using namespace mb2co::sim;

void BM_Line4At500kPc20ms(benchmark::State& state) {
  LineConfig c;
  c.stations = 4;
  c.bitrate_kbit = 500;
  c.pc.cycle_ns = 20 * kNsPerMs;
  c.node.skip_idle = state.range(0) != 0;
  Line line(c, nullptr);
  plant::PlantConfig pc;
  pc.step_ms = 20;
  for (int i = 0; i < c.stations; ++i) {
    line.pc(i).set_program(std::unique_ptr<PcProgram>(new PlantProgram(pc, 1)));
  }
  line.power_on_all();
  for (int i = 0; i < c.stations; ++i) {
    line.pc(i).start();
    line.at(kNsPerS + static_cast<SimNs>(i) * 7 * kNsPerMs,
            [&line, i] { line.set_button(i, gateway::kStart, true); });
    line.at(kNsPerS + static_cast<SimNs>(i) * 7 * kNsPerMs + 100 * kNsPerMs,
            [&line, i] { line.set_button(i, gateway::kStart, false); });
  }
  line.run_until(2 * kNsPerS);  // running line
  const SimNs slice = 10 * kNsPerS;
  double simulated_s = 0;
  for (auto _ : state) {
    line.run_for(slice);
    simulated_s += static_cast<double>(slice) / 1e9;
  }
  state.counters["x_real_time"] = benchmark::Counter(simulated_s, benchmark::Counter::kIsRate);
  state.counters["running"] = line.node(0).state().run;
}
BENCHMARK(BM_Line4At500kPc20ms)->Arg(1)->Arg(0)->ArgName("skip_idle")->Unit(benchmark::kMillisecond);

}  // namespace
