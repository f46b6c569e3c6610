// libFuzzer target: the plant config reader (shared/plant/config_parser) on
// any bytes. Invariants (violations abort): an accepted config passes
// check_plant_config() and builds a plant and a controller that run 100
// steps; a refused one leaves the output untouched and names a line within
// the text (0: the defaults are to blame) and a column.
#include <stdint.h>
#include <string.h>

#include "fuzz_support.h"
#include "plant/config_parser.h"
#include "plant/controller.h"
#include "plant/plant.h"

using namespace mb2co;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  plant::PlantConfig config;
  const plant::PlantConfig untouched = config;
  plant::ConfigError error;
  if (!plant::parse_plant_config(reinterpret_cast<const char*>(data), size, config, error)) {
    fuzz::require(memcmp(&config, &untouched, sizeof config) == 0, "a refused config changed the output");
    size_t lines = 1;
    for (size_t i = 0; i < size; ++i) lines += data[i] == '\n';
    fuzz::require(error.line <= lines, "an error beyond the last line");
    return 0;
  }
  plant::ConfigError again;
  uint16_t keys = 0;
  fuzz::require(plant::check_plant_config(config, again, keys), "an accepted config that does not check");
  plant::Plant p(config);
  plant::Controller c(plant::controller_config_for(config));
  plant::ControllerInputs in;
  for (int step = 0; step < 100; ++step) {
    in.plant = p.sensors();
    in.start_pressed = step == 1;
    p.step(c.step(in).plant);
  }
  return 0;
}
