// The station mode: one plant step and one controller step per cycle
// (docs/plant.md "The cycle"); the RUN command goes back to the gateway.
#pragma once
#include "cycle_mode.h"
#include "plant/controller.h"
#include "plant/plant.h"

namespace mb2co {
namespace pcapp {

class StationCycle : public CycleMode {
 public:
  /// `config` must have passed check_plant_config().
  StationCycle(const RegisterLayout& layout, const plant::PlantConfig& config);

  std::vector<Field> required_reads() const override;
  std::vector<Field> optional_reads() const override;
  std::vector<Field> writes() const override { return {Field::run_command}; }

  void step(const RegisterImage& in, RegisterImage& out) override;
  void step_offline() override;
  void link_lost() override;
  void safe_outputs(RegisterImage& out) const override;

  std::string take_event() override;
  std::string status() const override;
  std::vector<const char*> column_names() const override;
  void columns(std::vector<LogValue>& out) const override;
  std::string summary() const override;

  const plant::Controller& controller() const { return controller_; }
  const plant::Plant& plant() const { return plant_; }
  const Panel& panel() const { return panel_; }

 private:
  void note_changes(const plant::ControllerCounters& before, plant::State state_before);

  const RegisterLayout& layout_;
  plant::Plant plant_;
  plant::Controller controller_;
  Panel panel_;
  bool panel_known_ = false;  ///< a read since the start / the last link loss
  /// RUN commands written at the last two writes (the newest first): a
  /// command is confirmed once it preceded a whole read (see controller_inputs).
  bool run_written_[2] = {false, false};
  std::string event_;
};

const char* state_name(plant::State state);
const char* stop_cause_name(plant::StopCause cause);

}  // namespace pcapp
}  // namespace mb2co
