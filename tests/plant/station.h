// Test harness: one station = plant + controller closed in the loop the app
// and the simulator run, one cycle per plant step.
#pragma once
#include "plant/controller.h"
#include "plant/plant.h"

namespace mb2co {
namespace plant {

struct Station {
  /// Runs one idle cycle, as the app's first poll does: it sets the
  /// controller's baselines, so a START press after it is a press.
  explicit Station(const PlantConfig& config = PlantConfig())
      : plant(config), controller(controller_config_for(config)) {
    cycle();
  }

  /// One cycle: controller reads the sensors with the operator inputs in
  /// `panel`, then the plant integrates one step with its outputs.
  const ControllerOutputs& cycle() {
    panel.plant = plant.sensors();
    const ControllerOutputs& out = controller.step(panel);
    plant.step(out.plant);
    return out;
  }

  /// One cycle with START pressed, then one with it released.
  void press_start() {
    panel.start_pressed = true;
    cycle();
    panel.start_pressed = false;
    cycle();
  }

  /// A lost serial link: the app calls force_safe() instead of step() and
  /// keeps integrating the plant with what it returns.
  void outage(uint32_t cycles) {
    for (uint32_t i = 0; i < cycles; ++i) plant.step(controller.force_safe().plant);
  }

  void run(uint32_t cycles) {
    for (uint32_t i = 0; i < cycles; ++i) cycle();
  }

  Plant plant;
  Controller controller;
  ControllerInputs panel;
};

}  // namespace plant
}  // namespace mb2co
