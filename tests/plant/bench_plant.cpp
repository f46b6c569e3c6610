// One control cycle of a station: plant step + controller step, in steady
// running (moving, approaching, filling in their natural proportions).
#include <benchmark/benchmark.h>
#include <string.h>

#include "plant/config_parser.h"
#include "plant/controller.h"
#include "plant/plant.h"

namespace {

using namespace mb2co::plant;

// Kept out of line so callgrind can count it alone:
//   --toggle-collect='*control_cycle*'
__attribute__((noinline)) void control_cycle(Plant& plant, Controller& controller, ControllerInputs& in) {
  in.plant = plant.sensors();
  plant.step(controller.step(in).plant);
}

void BM_ControlCycle(benchmark::State& state) {
  const PlantConfig config;
  Plant plant(config);
  Controller controller(controller_config_for(config));
  ControllerInputs in;
  control_cycle(plant, controller, in);
  in.start_pressed = true;
  control_cycle(plant, controller, in);
  in.start_pressed = false;
  for (auto _ : state) {
    control_cycle(plant, controller, in);
  }
  if (!controller.running()) state.SkipWithError("the station stopped");
  state.counters["bottles_filled"] = static_cast<double>(controller.counters().bottles_filled);
}
// A fixed count, so every run (and callgrind's instruction count) covers the
// same cycles: 1000 bottles of 700 cycles each (200 moving/approach + 500 filling).
BENCHMARK(BM_ControlCycle)->Iterations(700000);

void BM_ParseExampleSizedConfig(benchmark::State& state) {
  static const char kText[] =
      "# station\nstep_ms = 10\nconveyor_speed_mm_s = 100\nconveyor_length_mm = 1000\n"
      "bottle_spacing_mm = 200\nvalve_position_mm = 500\nsensor_to_valve_mm = 0\n"
      "sensor_window_mm = 20\nfill_level_ml = 500\noverfill_ml = 510\n"
      "bottle_capacity_ml = 550\nfill_flow_ml_s = 100\nfill_timeout_ms = 10000\n";
  PlantConfig out;
  ConfigError error{};
  for (auto _ : state) {
    const bool ok = parse_plant_config(kText, strlen(kText), out, error);
    benchmark::DoNotOptimize(ok);
    if (!ok) state.SkipWithError(error.message);
  }
}
BENCHMARK(BM_ParseExampleSizedConfig);

}  // namespace
